#include "e2e/support/front_end.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <sys/socket.h>
#include <sys/un.h>
#include <thread>
#include <toml++/toml.h>
#include <unistd.h>

namespace tiltgate::test {

namespace {

using namespace std::chrono_literals;

// The value after the first of `names` in `command`, if it is there.
std::optional<std::string> option(const std::vector<std::string>& command,
                                  std::initializer_list<std::string_view> names) {
  for (std::size_t i = 0; i + 1 < command.size(); ++i)
    for (std::string_view name : names)
      if (command[i] == name) return command[i + 1];
  return std::nullopt;
}

std::optional<std::int64_t> integer(const std::optional<std::string>& text) {
  std::int64_t value = 0;
  if (!text) return std::nullopt;
  const auto [end, error] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (error != std::errc{} || end != text->data() + text->size()) return std::nullopt;
  return value;
}

// The [[bus]] a command's --port and line options describe. A value the command will refuse
// (--baud auto, --baud fast) is left out: the command reports it before it asks the gateway.
toml::table bus_from_options(const std::vector<std::string>& command, const std::string& port) {
  toml::table bus{{"name", "line1"}, {"port", port}};
  for (const auto& [option_name, key] :
       {std::pair{"--protocol", "protocol"}, {"--parity", "parity"}})
    if (auto value = option(command, {option_name})) bus.insert(key, *value);
  for (const auto& [option_name, key] : {std::pair{"--baud", "baud"}, {"--stop-bits", "stop_bits"},
                                         {"--master-address", "master_address"}})
    if (auto value = integer(option(command, {option_name}))) bus.insert(key, *value);
  return bus;
}

// The [[bus]] of the command's --config that its --bus names, or its --sensor's; none when the
// file cannot be read (the command says why).
std::optional<toml::table> bus_from_config(const std::vector<std::string>& command,
                                           const std::string& path) {
  toml::table file;
  try {
    file = toml::parse_file(path);
  } catch (const toml::parse_error&) {
    return std::nullopt;
  }
  std::optional<std::string> name = option(command, {"--bus"});
  if (const auto sensor = option(command, {"--sensor"}); sensor && !name)
    if (const toml::array* sensors = file["sensor"].as_array())
      for (const toml::node& entry : *sensors)
        if (entry.as_table() && (*entry.as_table())["name"].value<std::string>() == *sensor)
          name = (*entry.as_table())["bus"].value<std::string>();
  if (const toml::array* buses = file["bus"].as_array())
    for (const toml::node& entry : *buses)
      if (entry.as_table() && (*entry.as_table())["name"].value<std::string>() == name)
        return *entry.as_table();
  return std::nullopt;
}

// A configuration needs something to serve (docs/configuration.md, "Checks across tables"): a
// Modbus bus passes unit 247 through, which is polled never; a Rieker or Dyna bus gets a sensor
// at an address no test uses, polled once an hour (its first poll times out and it is offline).
toml::array something_to_serve(toml::table& bus) {
  const std::string protocol = bus["protocol"].value_or(std::string("rieker"));
  if (protocol.rfind("modbus", 0) == 0) {
    if (!bus.contains("pass_through")) bus.insert("pass_through", toml::array{247});
    return {};
  }
  const bool rieker = protocol == "rieker";
  return toml::array{toml::table{{"name", "unused"},
                                 {"bus", bus["name"].value_or(std::string())},
                                 {"model", rieker ? "h6" : "dyna"},
                                 {"address", rieker ? 65000 : 200},
                                 {"unit_id", 1},
                                 {"poll_ms", 3600000}}};
}

// Whether a Unix socket at `path` accepts a connection now.
bool accepts(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  path.copy(address.sun_path, sizeof address.sun_path - 1);
  const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return ok;
}

bool is_gateway_note(const std::string& line) {
  return line.rfind("through the running gateway: bus ", 0) == 0 ||
         line.rfind("note: the gateway runs ", 0) == 0;
}

}  // namespace

bool through_gateway() {
  const char* front_end = std::getenv("TILTGATE_E2E_FRONT_END");
  return front_end != nullptr && std::string_view(front_end) == "gateway";
}

bool skipped_through_gateway(std::string_view reason) {
  if (!through_gateway()) return false;
  std::cout << "skipped through a running gateway: " << reason << std::endl;
  return true;
}

ServingGateway::ServingGateway(const std::vector<std::string>& command)
    : socket_((dir_.path() / "control.sock").string()) {
  std::optional<toml::table> bus;
  if (auto port = option(command, {"--port"}))
    bus = bus_from_options(command, *port);
  else if (auto config = option(command, {"--config", "-c"}))
    bus = bus_from_config(command, *config);
  if (!bus) return;
  toml::array sensors = something_to_serve(*bus);
  // Modbus TCP on a free loopback port; HTTP off, since its default port would be every test's.
  toml::table config{{"server", toml::table{{"listen", "127.0.0.1"},
                                            {"port", std::int64_t{free_tcp_port()}},
                                            {"control_socket", socket_},
                                            {"state_dir", (dir_.path() / "state").string()}}},
                     {"http", toml::table{{"enabled", false}}},
                     {"bus", toml::array{*bus}}};
  if (!sensors.empty()) config.insert("sensor", std::move(sensors));
  std::ostringstream text;
  text << config << "\n";
  const auto file = dir_.write("gateway.toml", text.str());
  process_ = std::make_unique<GatewayProcess>(
      std::vector<std::string>{"run", "--config", file.string()}, dir_.path());
  const auto deadline = std::chrono::steady_clock::now() + 15s;
  while (!accepts(socket_) && process_->running() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(20ms);
  if (!accepts(socket_))
    std::cerr << "the gateway serving the bus did not open its control socket:\n"
              << text.str() << process_->log() << "\n";
}

ServingGateway::~ServingGateway() = default;

std::vector<std::string> ServingGateway::through(std::vector<std::string> command) const {
  if (!process_) return command;
  if (auto given = std::find(command.begin(), command.end(), "--control-socket");
      given != command.end() && given + 1 != command.end())
    command.erase(given, given + 2);
  command.insert(command.begin() + 1, {"--via-gateway", "--control-socket", socket_});
  return command;
}

CommandResult run_command(std::vector<std::string> args) {
  if (!through_gateway()) return run_tiltgate(std::move(args));
  const ServingGateway gateway(args);
  const std::vector<std::string> command = gateway.through(args);
  CommandResult result = run_tiltgate(command);
  std::istringstream err(result.err);
  std::string kept;
  bool went_through = false;
  for (std::string line; std::getline(err, line);) {
    if (is_gateway_note(line))
      went_through = true;
    else
      kept += line + "\n";
  }
  if (command != args && result.exit_code != 2)
    CHECK_MESSAGE(went_through, "not through the gateway: " << result.err);
  result.err = kept;
  return result;
}

CommandProcess::CommandProcess(std::vector<std::string> args, const std::filesystem::path& log_dir)
    : gateway_(through_gateway() ? args : std::vector<std::string>{}),
      process_(gateway_.through(args), log_dir) {}

}  // namespace tiltgate::test
