// build/tiltgate run with a Modbus RTU inclinometer whose map file shows a device-profile value
// (temperature) and writes another (filter_level), read and written with libmodbus: the value
// reaches its register, a write lands in the device and reads back, a value outside the map's
// range is refused before the device is asked, and the device's own exception is relayed.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/mixed_plant.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "unit/support/rtu_test_profile.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr const char* kMap = R"(
extends = "default"

[[point]]
name = "temperature"
table = "input"
address = 100
type = "int16"
source = "temperature"
scale = 10
units = "0.1 degC"

[[point]]
name = "filter_level"
table = "holding"
address = 100
type = "uint16"
write = "filter_level"
min = 0
max = 20
)";

constexpr int kLastNak = 12;  // common block input register

}  // namespace

TEST_CASE("a device profile's values are shown and written through a map file") {
  TempDir dir;
  const std::uint16_t port = free_tcp_port();
  modbus_rtu::RtuSimulatorOptions options;
  options.devices.push_back(modbus_rtu::rtu_inclinometer(9));
  options.link_path = (dir.path() / "ttyRtu").string();
  RtuSimulatorThread sim(options);
  dir.write("device.toml", kRtuTestProfile);
  dir.write("map.toml", kMap);
  const auto config = dir.write(
      "rtu.toml", server_table(port, "writes = true") +
                      bus_table("rtu-line", options.link_path,
                                "protocol = \"modbus-rtu\"\ntimeout_ms = 100\nretries = 1") +
                      sensor_table("mast", "rtu-line", "modbus-rtu", 9, 4,
                                   "poll_ms = 50\ndevice = \"device.toml\"\nmap = \"map.toml\""));
  GatewayProcess gateway({"run", "--config", config.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());
  ModbusClient client(port, 4);
  std::vector<std::uint16_t> temperature;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    temperature = client.input(100, 1);
    if (temperature.size() == 1) break;  // read once the sensor is online
    std::this_thread::sleep_for(50ms);
  }
  REQUIRE_MESSAGE(temperature.size() == 1, gateway.log());
  CHECK(temperature[0] == 215);  // the preset's 21.5 degC
  CHECK(client.holding(100, 1) == std::vector<std::uint16_t>{4});

  REQUIRE_MESSAGE(client.write(100, 6), gateway.log());
  CHECK(client.holding(100, 1) == std::vector<std::uint16_t>{6});

  // Outside the map's 0..20: refused by the gateway, the device never asked.
  CHECK_FALSE(client.write(100, 25));
  CHECK(client.exception() == 0x03);
  CHECK(client.input(kLastNak, 1) == std::vector<std::uint16_t>{65535});

  // Inside the map's and the profile's range but not the device's 1..8: the device's 03,
  // relayed; its code counted.
  CHECK_FALSE(client.write(100, 12));
  CHECK(client.exception() == 0x03);
  CHECK(client.input(kLastNak, 1) == std::vector<std::uint16_t>{3});
  CHECK(client.holding(100, 1) == std::vector<std::uint16_t>{6});
}
