#include "e2e/support/plant.h"

#include <doctest/doctest.h>

#include <fmt/format.h>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/modbus_client.h"
#include "rieker/simulator.h"

namespace tiltgate::test {

namespace {

rieker::SimulatedSensorOptions sensor(rieker::Model model, std::uint16_t address, double x, double y,
                                      std::string serial) {
  rieker::SimulatedSensorOptions s;
  s.model = model;
  s.address = address;
  s.angle_x = x;
  s.angle_y = y;
  s.serial = std::move(serial);
  return s;
}

}  // namespace

Plant::Plant(bool writes, int max_clients, const std::string& more_config) {
  rieker::RiekerSimulatorOptions options;
  options.sensors = {sensor(rieker::Model::h6, 223, 1.5, -2.25, "962285"),
                     sensor(rieker::Model::h6, 224, 10.0, 20.0, "962286"),
                     sensor(rieker::Model::h4360, 101, -30.5, 0, "777001")};
  options.link_path = (dir.path() / "ttyUSB0").string();
  sim = std::make_unique<SimulatorThread>(options);
  const auto config = dir.write("plant.toml", fmt::format(R"(
[server]
listen = "127.0.0.1"
port = {}
max_clients = {}
max_clients_per_host = {}
writes = {}

[[bus]]
name = "line1"
port = "{}"
protocol = "rieker"
baud = 125000
timeout_ms = 100
retries = 1
reopen_min_ms = 50
reopen_max_ms = 200

[[sensor]]
name = "boom-left"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50
stale_ms = 1000

[[sensor]]
name = "boom-right"
bus = "line1"
model = "h6"
address = 224
unit_id = 2
poll_ms = 50
stale_ms = 1000

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 3
poll_ms = 50
stale_ms = 1000
)", port, max_clients, max_clients, writes ? "true" : "false", options.link_path) + more_config);
  gateway = std::make_unique<GatewayProcess>(
      std::vector<std::string>{"--log-level", "debug", "run", "--config", config.string()}, dir.path());
  REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
}

bool Plant::wait_online(int unit, std::chrono::seconds limit) {
  ModbusClient client(port, unit);
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!client.input(0, 2).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

}  // namespace tiltgate::test
