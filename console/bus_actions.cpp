#include "console/bus_actions.h"

#include <unistd.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "console/child_command.h"
#include "driver/visible_text.h"
#include "toml/text_file.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

// A scan reads every address at most once per rate; 10 minutes is past any bus's worst case.
constexpr std::chrono::seconds kScanLimit{600};
constexpr std::chrono::seconds kRawLimit{20};

std::string quoted_value(std::string_view line) {
  const auto open = line.find('"');
  const auto close = open == std::string_view::npos ? open : line.find('"', open + 1);
  if (close == std::string_view::npos) return {};
  return std::string(line.substr(open + 1, close - open - 1));
}

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.remove_suffix(1);
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  return text;
}

}  // namespace

std::vector<ScanFound> found_in_scan_config(const std::string& text) {
  std::vector<ScanFound> found;
  std::size_t at = 0;
  ScanFound* current = nullptr;
  while (at < text.size()) {
    const auto end = text.find('\n', at);
    const std::string_view line(text.data() + at,
                                (end == std::string::npos ? text.size() : end) - at);
    at = end == std::string::npos ? text.size() : end + 1;
    if (line.starts_with("[")) {
      current = nullptr;
      if (trimmed(line) == "[[sensor]]") current = &found.emplace_back();
    }
    if (current == nullptr) continue;
    current->config += std::string(line) + "\n";
    if (line.starts_with("address = ")) current->address = std::atoll(line.data() + 10);
    if (line.starts_with("model = ")) current->model = quoted_value(line);
    if (line.starts_with("serial = ")) {
      current->serial = quoted_value(line);
      if (const auto mark = line.find("# firmware "); mark != std::string_view::npos)
        current->firmware = std::string(trimmed(line.substr(mark + 11)));
    }
  }
  for (ScanFound& sensor : found)
    while (sensor.config.size() > 1 && sensor.config.ends_with("\n\n")) sensor.config.pop_back();
  return found;
}

std::vector<std::string> BusActions::common_args(const std::string& command,
                                                 const std::string& bus,
                                                 const std::string& who) const {
  return {command, "--config", setup_.config_path, "--bus", bus, "--via-gateway",
          "--control-socket", setup_.control_socket, "--audit-as",
          fmt::format("console user {}", who)};
}

json BusActions::start_scan(const std::string& bus, const ScanRequest& request,
                            const std::string& who, unsigned& status) {
  if (setup_.control_socket.empty() || setup_.config_path.empty()) {
    status = 409;
    return json{{"error", "the console scans through the control socket: [server] "
                          "control_socket is off"}};
  }
  auto& scan = scans_[bus];
  if (scan && scan->running) {
    status = 409;
    return json{{"error", fmt::format("a scan of {} is running", bus)}};
  }
  scan = std::make_shared<Scan>();
  scan->running = true;
  char config_out[] = "/tmp/tiltgate-scan-XXXXXX";
  const int fd = ::mkstemp(config_out);
  if (fd >= 0) ::close(fd);
  std::vector<std::string> args = common_args("scan", bus, who);
  args.insert(args.end(), {"--progress-lines", "--config-out", config_out, "--force"});
  if (request.from > 0 || request.to > 0) {
    args.insert(args.end(), {"--from", std::to_string(request.from)});
    if (request.to > 0) args.insert(args.end(), {"--to", std::to_string(request.to)});
  }
  spdlog::info("web console: {} scans bus {}", visible_text(who), visible_text(bus));
  asio::co_spawn(executor_, run_scan(scan, std::move(args), std::string(config_out)),
                 asio::detached);
  status = 202;
  return json{{"running", true}};
}

asio::awaitable<void> BusActions::run_scan(std::shared_ptr<Scan> scan,
                                           std::vector<std::string> args, std::string config_out) {
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice (and
  // with it the scan it holds).
  const std::string wrote = "wrote " + config_out;  // the file is ours, not the user's
  std::function<void(std::string_view)> on_line = [scan, wrote](std::string_view line) {
    if (line == wrote) return;
    if (line.starts_with("progress ")) {
      unsigned long done = 0, total = 0;
      if (std::sscanf(std::string(line).c_str(), "progress %lu %lu", &done, &total) == 2 &&
          total > 0)
        scan->progress = double(done) / double(total);
      return;
    }
    scan->output += std::string(line) + "\n";
  };
  const ChildResult result =
      co_await run_child_command(executor_, std::move(args), kScanLimit, std::move(on_line));
  if (auto text = toml_input::read_text_file(config_out); text && result.exit_code == 0)
    scan->found = found_in_scan_config(*text);
  ::unlink(config_out.c_str());
  if (!result.error.empty())
    scan->error = result.error;
  else if (result.timed_out)
    scan->error = "the scan took too long and was stopped";
  else if (result.exit_code == 1 && scan->found.empty())
    scan->error = "no sensor answered";
  else if (result.exit_code != 0)
    scan->error = fmt::format("the scan failed (exit code {})", result.exit_code);
  scan->progress = 1;
  scan->running = false;
}

json BusActions::scan_state(const std::string& bus) const {
  const auto found = scans_.find(bus);
  if (found == scans_.end() || !found->second)
    return json{{"running", false}, {"progress", 0}, {"output", ""}, {"found", json::array()},
                {"error", nullptr}};
  const Scan& scan = *found->second;
  json sensors = json::array();
  for (const ScanFound& sensor : scan.found)
    sensors.push_back({{"address", sensor.address},
                       {"model", sensor.model},
                       {"serial", sensor.serial},
                       {"firmware", sensor.firmware},
                       {"config", sensor.config}});
  return json{{"running", scan.running},
              {"progress", scan.progress},
              {"output", scan.output},
              {"found", sensors},
              {"error", scan.error.empty() ? json(nullptr) : json(scan.error)}};
}

asio::awaitable<json> BusActions::raw(std::string bus, RawRequest request, std::string who,
                                      unsigned& status) {
  if (setup_.control_socket.empty() || setup_.config_path.empty()) {
    status = 409;
    co_return json{{"error", "the console sends raw frames through the control socket: "
                             "[server] control_socket is off"}};
  }
  std::vector<std::string> args = common_args("raw", bus, who);
  args.insert(args.end(), {"--address", std::to_string(request.address), "--function",
                           std::to_string(request.function)});
  if (!request.data.empty()) args.insert(args.end(), {"--data", request.data});
  spdlog::info("web console: {} sends function {} to address {} on bus {}", visible_text(who),
               request.function, request.address, visible_text(bus));
  std::function<void(std::string_view)> no_lines;  // named: see run_scan()
  const ChildResult result =
      co_await run_child_command(executor_, std::move(args), kRawLimit, std::move(no_lines));
  json reply{{"sent", nullptr}, {"received", nullptr}, {"verdict", ""}, {"decoded", ""},
             {"error", nullptr}, {"output", result.output}};
  std::string decoded, errors;
  std::size_t at = 0;
  const std::string& out = result.output;
  while (at < out.size()) {
    const auto end = out.find('\n', at);
    const std::string line = out.substr(at, (end == std::string::npos ? out.size() : end) - at);
    at = end == std::string::npos ? out.size() : end + 1;
    if (line.starts_with("sent:")) {
      std::string hex = line.substr(5);
      hex = hex.substr(0, hex.find("  ("));
      reply["sent"] = std::string(trimmed(hex));
    } else if (line.starts_with("received:")) {
      const std::string rest = line.substr(9);
      const auto paren = rest.rfind("  (");
      if (rest.find("nothing") != std::string::npos) {
        reply["verdict"] = std::string(trimmed(rest));
      } else {
        reply["received"] = std::string(trimmed(rest.substr(0, paren)));
        if (paren != std::string::npos) {
          std::string verdict = rest.substr(paren + 3);
          if (!verdict.empty() && verdict.back() == ')') verdict.pop_back();
          reply["verdict"] = verdict;
        }
      }
    } else if (line.starts_with("tiltgate raw:") || line.starts_with("tiltgate:")) {
      errors += line + "\n";
    } else {
      decoded += line + "\n";
    }
  }
  reply["decoded"] = decoded;
  if (!result.error.empty())
    reply["error"] = result.error;
  else if (result.timed_out)
    reply["error"] = "the command took too long and was stopped";
  else if (result.exit_code != 0)
    reply["error"] = errors.empty() ? fmt::format("exit code {}", result.exit_code) : errors;
  status = result.exit_code == 2 ? 400 : 200;
  co_return reply;
}

}  // namespace tiltgate
