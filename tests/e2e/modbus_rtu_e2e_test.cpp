// build/tiltgate run with one Modbus RTU bus: an inclinometer on the RTU simulator (its own
// thread and pseudo-terminal), described by the example device profile, read with libmodbus.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <fmt/format.h>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/mixed_plant.h"
#include "modbus_rtu/family.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("a Modbus RTU inclinometer's angles reach the common block through the gateway") {
  TempDir dir;
  const std::uint16_t port = free_tcp_port();
  modbus_rtu::RtuSimulatorOptions options;
  options.devices.push_back(modbus_rtu::rtu_inclinometer(17));
  modbus_rtu::set_inclinometer_angles(options.devices.back(), 12.5, -7.25);
  options.link_path = (dir.path() / "ttyRtu").string();
  RtuSimulatorThread sim(options);
  const auto config = dir.write(
      "rtu.toml",
      server_table(port) +
          bus_table("rtu-line", options.link_path,
                    "protocol = \"modbus-rtu\"\nbaud = 19200\ntimeout_ms = 100\nretries = 1") +
          sensor_table("boom", "rtu-line", "modbus-rtu", 17, 3,
                       fmt::format("poll_ms = 50\ndevice = \"{}/examples/devices/rtu-inclinometer.toml\"",
                                   TILTGATE_SOURCE_DIR)));
  GatewayProcess gateway({"--log-level", "debug", "run", "--config", config.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());
  ModbusClient client(port, 3);
  std::vector<std::uint16_t> words;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    words = client.input(0, 38);
    if (words.size() == 38 && (words[6] & 0x01) == 0x01) break;  // online
    std::this_thread::sleep_for(50ms);
  }
  REQUIRE_MESSAGE(words.size() == 38, gateway.log());
  CHECK((words[6] & 0x01) == 0x01);
  CHECK(float_at(words, 0) == 12.5f);
  CHECK(float_at(words, 2) == -7.25f);
  CHECK(words[37] == modbus_rtu::kFamily.models[0].model_code);
}
