#include "e2e/support/plant.h"

#include <doctest/doctest.h>

#include <fmt/format.h>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
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
  std::string text = server_table(port, fmt::format("max_clients = {0}\nmax_clients_per_host = {0}\n"
                                                    "writes = {1}",
                                                    max_clients, writes ? "true" : "false")) +
                     bus_table("line1", options.link_path,
                               "protocol = \"rieker\"\nbaud = 125000\ntimeout_ms = 100\nretries = 1\n"
                               "reopen_min_ms = 50\nreopen_max_ms = 200");
  const std::string_view timing = "poll_ms = 50\nstale_ms = 1000";
  text += sensor_table("boom-left", "line1", "h6", 223, 1, timing) +
          sensor_table("boom-right", "line1", "h6", 224, 2, timing) +
          sensor_table("mast", "line1", "h4360", 101, 3, timing);
  const auto config = dir.write("plant.toml", text + more_config);
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
