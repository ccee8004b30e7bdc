// [[bus]] pass_through: unit ids forwarded to the device with that address on the bus. Read
// as 1..247 on a protocol that can forward Modbus requests; a unit id is passed through once,
// on one bus, and is never also a sensor's; no sensor on the bus shares a passed-through
// device's address.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// Lines 1..5: a Modbus RTU bus "rtu" whose line 5 is `pass_through`.
std::string rtu_bus(std::string_view name, std::string_view port, std::string_view pass_through) {
  return "[[bus]]\nname = \"" + std::string(name) + "\"\nport = \"" + std::string(port) +
         "\"\nprotocol = \"modbus-rtu\"\npass_through = " + std::string(pass_through) + "\n";
}

// Seven lines: a Modbus RTU sensor on `bus`; its address is the 5th line, unit_id the 6th.
std::string rtu_sensor(int address, int unit_id, std::string_view bus = "rtu") {
  return "[[sensor]]\nname = \"boom\"\nbus = \"" + std::string(bus) + "\"\nmodel = \"modbus-rtu\"\naddress = " +
         std::to_string(address) + "\nunit_id = " + std::to_string(unit_id) + "\ndevice = \"" +
         TILTGATE_SOURCE_DIR + "/examples/devices/rtu-inclinometer.toml\"\n";
}

const std::string kBus = rtu_bus("rtu", "/dev/ttyUSB5", "[30, 31]");

}  // namespace

TEST_CASE("config: a Modbus RTU bus passes unit ids through, next to its cached sensors") {
  const Config config = loads(kBus + rtu_sensor(17, 3));
  REQUIRE(config.buses.size() == 1);
  CHECK(config.buses[0].pass_through == std::vector<std::uint8_t>{30, 31});
  CHECK(config.sensors.size() == 1);
}

TEST_CASE("config: a bus that only passes unit ids through needs no sensor") {
  const Config config = loads(kBus);
  CHECK(config.sensors.empty());
  CHECK(config.buses[0].pass_through == std::vector<std::uint8_t>{30, 31});
}

TEST_CASE("config: pass_through takes unit ids 1..247, each once") {
  expect_error(rtu_bus("rtu", "/dev/ttyUSB5", "[30, 0]"), 5, "bus[0].pass_through",
               "0 is out of range, expected an array of integers in 1..247");
  expect_error(rtu_bus("rtu", "/dev/ttyUSB5", "[248]"), 5, "bus[0].pass_through",
               "248 is out of range, expected an array of integers in 1..247");
  expect_error(rtu_bus("rtu", "/dev/ttyUSB5", "[\"30\"]"), 5, "bus[0].pass_through",
               "expected an array of integers in 1..247, found a string");
  expect_error(rtu_bus("rtu", "/dev/ttyUSB5", "30"), 5, "bus[0].pass_through",
               "expected an array, got an integer");
  expect_error(rtu_bus("rtu", "/dev/ttyUSB5", "[30, 31, 30]"), 5, "bus[0].pass_through",
               "unit id 30 is listed twice");
}

TEST_CASE("config: pass_through is refused on a bus whose protocol cannot forward") {
  expect_error(with_bus_keys("pass_through = [30]\n"), 4, "bus[0].pass_through",
               "protocol rieker cannot forward Modbus requests");
}

TEST_CASE("config: a unit id is passed through on one bus only") {
  expect_error(kBus + rtu_bus("rtu2", "/dev/ttyUSB6", "[32, 31]"), 10, "bus[1].pass_through",
               "unit id 31 is already passed through on bus \"rtu\" (line 1)");
}

TEST_CASE("config: a unit id is a sensor or passed through, never both") {
  // Reported at whichever of the two comes later, naming the other's place.
  expect_error(kBus + rtu_sensor(17, 30), 11, "sensor[0].unit_id",
               "unit_id 30 is passed through on bus \"rtu\" (line 1); a unit id is either a "
               "sensor or passed through");
  expect_error(rtu_sensor(17, 31) + kBus, 12, "bus[0].pass_through",
               "unit id 31 is the unit_id of sensor \"boom\" (line 1); a unit id is either a "
               "sensor or passed through");
  // Also a sensor on another bus.
  expect_error(valid_plus(rtu_bus("rtu", "/dev/ttyUSB5", "[1]")), 14, "bus[1].pass_through",
               "unit id 1 is the unit_id of sensor \"boom\" (line 4); a unit id is either a "
               "sensor or passed through");
}

TEST_CASE("config: no sensor on the bus has the address of a device passed through") {
  expect_error(kBus + rtu_sensor(31, 3), 10, "sensor[0].address",
               "31 is passed through on bus \"rtu\" (line 1): the sensor and the device passed "
               "through would both answer it");
  expect_error(rtu_sensor(30, 3) + kBus, 12, "bus[0].pass_through",
               "30 is the address of sensor \"boom\" (line 1) on this bus: the sensor and the "
               "device passed through would both answer it");
  // On another bus the same address is another device.
  loads(kBus + rtu_bus("other", "/dev/ttyUSB6", "[40]") + rtu_sensor(31, 3, "other"));
}
