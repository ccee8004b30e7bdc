// The commissioning commands through a running gateway's control socket: `tiltgate run` on a
// simulated Rieker bus serves sensor "boom" (address 5) to a Modbus client while scan, info,
// raw, watch and set talk to a new sensor at 223 on the same tty; the client's readings keep
// coming without a gap longer than two poll periods. A sensor the gateway polls, re-addressed
// this way, is followed at once; a missing gateway, a tty it does not own and a rate it cannot
// change are each refused clearly.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/output_checks.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate::test;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto kPollPeriod = 200ms;
// Input registers of the built-in map (docs/register-maps.md, "Default register map").
constexpr int kSampleSeq = 15;
constexpr int kBusAddress = 14;
// Holding register 0: the filter setting.
constexpr int kFilter = 0;

// `tiltgate run` with sensor "boom" at address 5 of the simulator's bus, and its control socket.
struct RunningGateway {
  SimulatorProcess sim{{"rieker", "--sensors", "h6:5,h6:223", "--baud", "125000"}};
  TempDir dir;
  std::string socket = (dir.path() / "control.sock").string();
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  std::filesystem::path config;
  std::unique_ptr<GatewayProcess> process;

  explicit RunningGateway(std::chrono::milliseconds poll = kPollPeriod) {
    config = dir.write(
        "gateway.toml",
        server_table(port, fmt::format("writes = true\ncontrol_socket = \"{}\"", socket)) +
            http_table(http_port) + bus_table("line1", sim.tty()) +
            sensor_table("boom", "line1", "h6", 5, 1, fmt::format("poll_ms = {}", poll.count())));
    process = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(process->wait_listening(port), process->log());
    const auto deadline = Clock::now() + 10s;
    while (!std::filesystem::exists(socket) && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
    REQUIRE_MESSAGE(std::filesystem::exists(socket), process->log());
  }

  // `tiltgate COMMAND --via-gateway --control-socket S --port TTY ARGS...`
  CommandResult through(const std::string& command, std::vector<std::string> args) const {
    std::vector<std::string> full{command, "--via-gateway", "--control-socket", socket,
                                  "--port", sim.tty()};
    full.insert(full.end(), args.begin(), args.end());
    return run_tiltgate(full);
  }
};

// A PLC reading boom's sample counter as fast as it likes; notes when each new reading shows.
class SampleWatcher {
 public:
  explicit SampleWatcher(std::uint16_t port) : thread_([this, port] { run(port); }) {}
  ~SampleWatcher() { stop(); }
  void stop() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
  }
  // The longest time between two new readings, and how many there were.
  std::chrono::milliseconds longest_gap() const {
    Clock::duration longest{0};
    for (std::size_t i = 1; i < changes_.size(); ++i)
      longest = std::max(longest, changes_[i] - changes_[i - 1]);
    return std::chrono::duration_cast<std::chrono::milliseconds>(longest);
  }
  std::size_t readings() const { return changes_.size(); }
  int failed_reads() const { return failed_; }

 private:
  void run(std::uint16_t port) {
    ModbusClient client(port, 1);
    std::optional<std::uint16_t> last;
    while (!stopping_) {
      const auto words = client.input(kSampleSeq, 1);
      if (words.empty()) {
        ++failed_;
      } else if (last != words[0]) {
        if (last) changes_.push_back(Clock::now());
        last = words[0];
      }
      std::this_thread::sleep_for(5ms);
    }
  }

  std::atomic<bool> stopping_{false};
  std::vector<Clock::time_point> changes_;
  int failed_ = 0;
  std::thread thread_;
};

}  // namespace

TEST_CASE("scan, info, raw, watch and set through a running gateway while a PLC keeps reading another sensor") {
  RunningGateway gateway;
  SampleWatcher plc(gateway.port);
  std::this_thread::sleep_for(3 * kPollPeriod);  // a few readings before the commands start

  const auto scan = gateway.through("scan", {"--from", "1", "--to", "30"});
  INFO("scan: " << scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  CHECK(has(scan.err, "through the running gateway: bus line1"));
  CHECK(has(scan.out, "9600005"));  // boom, found while the gateway polls it

  const auto info = gateway.through("info", {"--address", "223"});
  INFO("info: " << info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(has(info.out, "serial:     9600223"));

  const auto raw = gateway.through("raw", {"--address", "223", "--function", "4"});
  INFO("raw: " << raw.out << raw.err);
  CHECK(raw.exit_code == 0);

  const auto watch = gateway.through("watch", {"--address", "223", "--count", "5", "--interval", "20"});
  INFO("watch: " << watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  CHECK(has(watch.out, "9600223"));

  const auto set = gateway.through("set", {"--address", "223", "address", "7"});
  INFO("set: " << set.out << set.err);
  CHECK(set.exit_code == 0);
  const auto moved = gateway.through("info", {"--address", "7"});
  CHECK(moved.exit_code == 0);
  CHECK(has(moved.out, "serial:     9600223"));

  plc.stop();
  INFO("gateway log: " << gateway.process->log());
  CHECK(plc.failed_reads() == 0);
  CHECK(plc.readings() >= 5);
  CHECK(plc.longest_gap() <= 2 * kPollPeriod);
}

TEST_CASE("a sensor the gateway polls, re-addressed through it, is followed at once") {
  // Polled all the time, so a poll is due the moment the sensor moves.
  RunningGateway gateway(20ms);
  ModbusClient plc(gateway.port, 1);
  const auto set = gateway.through("set", {"--address", "5", "address", "9"});
  INFO(set.out << set.err << gateway.process->log());
  REQUIRE(set.exit_code == 0);
  CHECK(has(set.out, "gateway: sensor line1/boom is polled at address 9 from now on"));
  // Boom answers at 9 and the gateway reads it there: its address register shows 9 and new
  // readings keep coming.
  const auto before = plc.input(kSampleSeq, 1);
  REQUIRE_FALSE(before.empty());
  std::this_thread::sleep_for(300ms);
  const auto after = plc.input(kSampleSeq, 1);
  REQUIRE_FALSE(after.empty());
  CHECK(after[0] != before[0]);
  const auto address = plc.input(kBusAddress, 1);
  REQUIRE_FALSE(address.empty());
  CHECK(address[0] == 9);
  // The gateway held its polls while the sensor moved: none failed at the old address.
  CHECK_FALSE(has(gateway.process->log(), "stopped answering"));
}

TEST_CASE("a setting changed through the running gateway, by set or by a Modbus write, is what its holding register reads") {
  RunningGateway gateway;
  ModbusClient plc(gateway.port, 1);
  const auto filter = [&] {
    const auto words = plc.holding(kFilter, 1);
    REQUIRE_FALSE(words.empty());
    return words[0];
  };
  // The Rieker protocol reads no filter back: unknown until one is acknowledged.
  CHECK(filter() == 65535);

  // The issue's scenario: the command finds the gateway through the configuration's control
  // socket and carries its writes on the gateway's bus.
  const auto set = run_tiltgate(
      {"set", "--config", gateway.config.string(), "--sensor", "boom", "filter", "2"});
  INFO(set.out << set.err << gateway.process->log());
  REQUIRE(set.exit_code == 0);
  CHECK(has(set.err, "through the running gateway"));
  CHECK(filter() == 2);

  // A Modbus write, then the command again: each door updates the same record.
  CHECK(plc.write(kFilter, 5));
  CHECK(filter() == 5);
  const auto again = run_tiltgate(
      {"set", "--config", gateway.config.string(), "--sensor", "boom", "filter", "3"});
  INFO(again.out << again.err);
  REQUIRE(again.exit_code == 0);
  CHECK(filter() == 3);
  // The API shows the same record: the address known from the start, the zeros never set.
  const Response api = get(gateway.http_port, "/api/sensors/boom");
  CHECK(has(api.body, R"("settings":{"filter":3,"zero_x":null,"zero_y":null,"baud_code":null,)"
                      R"("bus_address":5})"));
  CHECK(has(gateway.process->log(), "sensor \"boom\": filter = 3 set by a commissioning command"));
}

TEST_CASE("through a gateway: none listening, a tty it does not own, and a rate it cannot change are refused") {
  TempDir dir;
  SimulatorProcess lone({"rieker", "--sensors", "h6:223"});
  const std::string nowhere = (dir.path() / "none.sock").string();
  const auto none = run_tiltgate({"info", "--via-gateway", "--control-socket", nowhere, "--port",
                                  lone.tty(), "--address", "223"});
  CHECK(none.exit_code == 1);
  CHECK(has(none.err, "no gateway is listening on " + nowhere));
  // Without --via-gateway the command opens the tty itself when no gateway serves it.
  const auto direct = run_tiltgate({"info", "--control-socket", nowhere, "--port", lone.tty(),
                                    "--address", "223"});
  CHECK(direct.exit_code == 0);
  CHECK_FALSE(has(direct.err, "through the running gateway"));

  RunningGateway gateway;
  const auto elsewhere = run_tiltgate({"info", "--via-gateway", "--control-socket", gateway.socket,
                                       "--port", lone.tty(), "--address", "223"});
  CHECK(elsewhere.exit_code == 1);
  CHECK(has(elsewhere.err, "the gateway has no bus on " + lone.tty()));
  CHECK(has(elsewhere.err, "line1 on " + gateway.sim.tty()));

  // Its tty is locked: a command that does not find its control socket is told it is in use
  // rather than talking over the gateway's polls.
  const auto over = run_tiltgate({"info", "--control-socket", nowhere, "--port", gateway.sim.tty(),
                                  "--address", "223"});
  CHECK(over.exit_code == 1);
  CHECK(has(over.err, gateway.sim.tty() + " is in use: a running gateway"));

  // A gateway that owns the tty is used without being asked.
  const auto found = run_tiltgate({"info", "--control-socket", gateway.socket, "--port",
                                   gateway.sim.tty(), "--address", "223"});
  CHECK(found.exit_code == 0);
  CHECK(has(found.err, "through the running gateway: bus line1"));

  // --baud auto needs the tty: with --via-gateway that is a usage error (2), said before the
  // bus is touched; a gateway found on its own is refused before the first probe (1).
  const auto auto_baud = gateway.through("scan", {"--baud", "auto", "--from", "1", "--to", "3"});
  INFO(auto_baud.out << auto_baud.err);
  CHECK(auto_baud.exit_code == 2);
  CHECK(has(auto_baud.err, "--baud auto: not with --via-gateway"));
  CHECK_FALSE(has(auto_baud.err, "without --via-gateway"));
  const auto found_auto = run_tiltgate({"scan", "--control-socket", gateway.socket, "--port",
                                        gateway.sim.tty(), "--baud", "auto", "--from", "1",
                                        "--to", "3"});
  INFO(found_auto.out << found_auto.err);
  CHECK(found_auto.exit_code == 1);
  CHECK(has(found_auto.err, "the running gateway keeps " + gateway.sim.tty() + " at 125000 baud"));
  CHECK_FALSE(has(found_auto.out, "probe(s)"));  // refused before the first
}

TEST_CASE("through a gateway whose tty is missing, a command is told the gateway's bus is not open, not that the sensor is silent") {
  TempDir dir;
  const std::string missing = (dir.path() / "ttyUSB9").string();
  const std::string socket = (dir.path() / "control.sock").string();
  const std::uint16_t port = free_tcp_port();
  const auto config = dir.write(
      "gateway.toml", server_table(port, fmt::format("control_socket = \"{}\"", socket)) +
                          http_table(free_tcp_port()) + bus_table("line1", missing) +
                          sensor_table("boom", "line1", "h6", 5, 1));
  GatewayProcess gateway({"run", "--config", config.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());
  const auto deadline = Clock::now() + 10s;
  while (!std::filesystem::exists(socket) && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
  const auto info = run_tiltgate({"info", "--via-gateway", "--control-socket", socket, "--port",
                                  missing, "--address", "5"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 1);
  CHECK(has(info.err, "nothing sent to address 5: the gateway's bus line1 on " + missing +
                          " is not open"));
  CHECK_FALSE(has(info.err, "hint: check the baud rate"));
}
