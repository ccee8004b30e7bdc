// The audit trail end to end (docs/operations.md, "The audit trail"): build/tiltgate serving a
// simulated Rieker sensor records a Modbus write and a `tiltgate set --via-gateway` each with
// who made it, the sensor's NAK and its silence as such, in the journal ("audit: ...") and in
// /metrics; the records are kept in [server] state_dir and are still there, for the gateway
// and for `tiltgate audit`, after a restart.
#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/output_checks.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr int kFilter = 0;  // holding register 0: the filter setting (the built-in H6 map)

// One H6 "boom" at address 223 on bus "line1", served by `tiltgate run` with writes on, a
// control socket, the status API and its state_dir in a temporary folder.
struct AuditedGateway {
  TempDir dir;
  std::string tty = (dir.path() / "ttyUSB0").string();
  std::string socket = (dir.path() / "control.sock").string();
  std::string state_dir = (dir.path() / "state").string();
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::filesystem::path config;
  std::unique_ptr<GatewayProcess> gateway;

  AuditedGateway() {
    rieker::RiekerSimulatorOptions options;
    rieker::SimulatedSensorOptions boom;
    boom.model = rieker::Model::h6;
    boom.address = 223;
    boom.serial = "962285";
    options.sensors = {boom};
    options.link_path = tty;
    sim = std::make_unique<SimulatorThread>(options);
    config = dir.write(
        "gateway.toml",
        server_table(port, fmt::format("writes = true\ncontrol_socket = \"{}\"\nstate_dir = \"{}\"",
                                       socket, state_dir)) +
            http_table(http_port) +
            bus_table("line1", tty, "protocol = \"rieker\"\nbaud = 125000\ntimeout_ms = 100") +
            sensor_table("boom", "line1", "h6", 223, 1, "poll_ms = 100"));
    start();
  }

  void start() {
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
    ModbusClient plc(port, 1);
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (plc.input(0, 2).empty() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(50ms);
    REQUIRE_MESSAGE(std::filesystem::exists(socket), gateway->log());
  }

  // The next Set Filter the sensor gets is refused (NAK 4) or goes unanswered.
  void nak_next_filter() {
    sim->call([](rieker::RiekerSimulator& s) {
      s.sensor(0).faults().by_function[rieker::Function::set_filter].nak = 1;
      s.sensor(0).faults().by_function[rieker::Function::set_filter].nak_code =
          rieker::NakCode::data_invalid;
    });
  }
  void silence_filter(int queries) {
    sim->call([queries](rieker::RiekerSimulator& s) {
      s.sensor(0).faults().by_function[rieker::Function::set_filter].silent = queries;
    });
  }

  // `tiltgate set --via-gateway ... filter VALUE` (and any ARGS before the setting).
  CommandResult set_filter(int value, std::vector<std::string> args = {}) const {
    std::vector<std::string> full{"set", "--via-gateway", "--control-socket", socket, "--port", tty,
                                  "--protocol", "rieker", "--address", "223"};
    full.insert(full.end(), args.begin(), args.end());
    full.push_back("filter");
    full.push_back(std::to_string(value));
    return run_tiltgate(full);
  }

  CommandResult audit(std::vector<std::string> args = {}) const {
    std::vector<std::string> full{"audit", "--state-dir", state_dir};
    full.insert(full.end(), args.begin(), args.end());
    return run_tiltgate(full);
  }
};

}  // namespace

TEST_CASE("a Modbus write and a set through the control socket are audited with who, the NAK and the time-out, and kept across a restart") {
  AuditedGateway plant;
  ModbusClient plc(plant.port, 1);

  // Modbus: acknowledged, then refused by the sensor.
  REQUIRE(plc.write(kFilter, 2));
  plant.nak_next_filter();
  CHECK_FALSE(plc.write(kFilter, 3));
  std::string log = plant.gateway->log();
  INFO("gateway log: " << log);
  CHECK(has(log, "audit: door modbus, who 127.0.0.1:"));
  CHECK(has(log, ": line1/boom filter = 2: ack"));  // the Rieker filter is not read back
  CHECK(has(log, ": line1/boom filter 2 -> 3: nak 0x"));

  // The control socket: acknowledged, unanswered, acknowledged again. (A console user's changes
  // are the console's door, run in the gateway: tests/e2e/console_api_test.py.)
  const CommandResult set = plant.set_filter(4);
  INFO("set: " << set.out << set.err);
  CHECK(set.exit_code == 0);
  plant.silence_filter(1000);
  const CommandResult silent = plant.set_filter(5);
  INFO("silent set: " << silent.out << silent.err);
  CHECK(silent.exit_code == 1);
  plant.silence_filter(0);
  const CommandResult again = plant.set_filter(6);
  INFO("set again: " << again.out << again.err);
  CHECK(again.exit_code == 0);
  log = plant.gateway->log();
  CHECK(has(log, "audit: door control socket, who user "));
  CHECK(has(log, ": line1/boom filter 2 -> 4: ack"));
  CHECK(has(log, ": line1/boom filter 4 -> 5: timeout"));
  CHECK(has(log, ": line1/boom filter 4 -> 6: ack"));

  const Response metrics = get(plant.http_port, "/metrics");
  INFO("metrics: " << metrics.body);
  CHECK(has(metrics.body, "tiltgate_audit_records_total{door=\"modbus\",result=\"ack\"} 1\n"));
  CHECK(has(metrics.body, "tiltgate_audit_records_total{door=\"modbus\",result=\"nak\"} 1\n"));
  CHECK(has(metrics.body,
            "tiltgate_audit_records_total{door=\"control socket\",result=\"ack\"} 2\n"));
  CHECK(has(metrics.body,
            "tiltgate_audit_records_total{door=\"control socket\",result=\"timeout\"} 1\n"));

  // Restarted on the same state_dir: the gateway finds its five records, adds to them, and
  // `tiltgate audit` shows them all, beside it and filtered.
  REQUIRE(plant.gateway->terminate() == 0);
  plant.start();
  CHECK(has(plant.gateway->log(), "(5 records)"));
  ModbusClient after_restart(plant.port, 1);
  const bool written = after_restart.write(kFilter, 1);
  INFO("after the restart: exception " << after_restart.exception() << ", "
                                       << plant.gateway->log());
  REQUIRE(written);
  // The trail's writer thread takes the record to disk a moment after the write's answer.
  CommandResult all = plant.audit();
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!has(all.out, "line1/boom filter = 1: ack\n") &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
    all = plant.audit();
  }
  INFO("audit: " << all.out << all.err);
  CHECK(all.exit_code == 0);
  CHECK(has(all.out, "line1/boom filter = 2: ack\n"));
  CHECK(has(all.out, "line1/boom filter 2 -> 3: nak 0x"));
  CHECK(has(all.out, "line1/boom filter 4 -> 5: timeout\n"));
  CHECK(has(all.out, "line1/boom filter 4 -> 6: ack\n"));
  CHECK(has(all.out, "line1/boom filter = 1: ack\n"));  // the new gateway knows no filter yet
  const CommandResult modbus = plant.audit({"--door", "modbus", "--limit", "1"});
  CHECK(modbus.out.find("door modbus") != std::string::npos);
  CHECK(modbus.out.find("filter = 1: ack") != std::string::npos);
  CHECK(modbus.out.find("door control socket") == std::string::npos);
  CHECK(modbus.out.find("nak") == std::string::npos);  // only the newest
}

TEST_CASE("a raw request through the control socket that may change a sensor is one record of what the gateway carried, and a raw read is none") {
  AuditedGateway plant;
  auto raw = [&](int function, std::string data) {
    std::vector<std::string> args{"raw",       "--via-gateway", "--control-socket", plant.socket,
                                  "--port",    plant.tty,       "--protocol",       "rieker",
                                  "--address", "223",           "--function",       std::to_string(function)};
    if (!data.empty()) args.insert(args.end(), {"--data", data});
    return run_tiltgate(args);
  };
  // Set Filter Response, without the unlock before it: the sensor refuses it (NAK 4), which
  // the gateway reads from the reply itself.
  const CommandResult written = raw(41, "05");
  INFO("raw 41: " << written.out << written.err);
  CHECK(written.exit_code == 1);
  const CommandResult read = raw(37, "");  // Get Serial
  INFO("raw 37: " << read.out << read.err);
  CHECK(read.exit_code == 0);
  const CommandResult set = plant.set_filter(3);  // its own record only, the setting's
  INFO("set: " << set.out << set.err);
  CHECK(set.exit_code == 0);
  CommandResult all = plant.audit({"--door", "control socket"});
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!has(all.out, "filter") && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
    all = plant.audit({"--door", "control socket"});
  }
  INFO("audit: " << all.out << all.err);
  CHECK(has(all.out, "line1/boom function 41 (set filter response) = 05: nak 0x04\n"));
  CHECK_FALSE(has(all.out, "function 37"));
  CHECK_FALSE(has(all.out, "= 03:"));  // the set's transaction is not recorded beside it
  CHECK(has(all.out, "line1/boom filter"));
  std::size_t records = 0;
  for (std::size_t at = all.out.find("door control socket"); at != std::string::npos;
       at = all.out.find("door control socket", at + 1))
    ++records;
  CHECK(records == 2);
}
