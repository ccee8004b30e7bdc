// Checks across the tables of one configuration: unique names, unit ids, bus addresses and
// ttys, and sensors on buses that exist.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("config: bus and sensor names must be unique") {
  expect_error(valid_plus("[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB1\"\n"), 11,
               "bus[1].name", "duplicate bus name \"line1\", first declared at line 1");
  expect_error(valid_plus(sensor_text("boom", "line1", 224, 2)), 11, "sensor[1].name",
               "duplicate sensor name \"boom\", first declared at line 4");
}

TEST_CASE("config: two sensors cannot share a unit id") {
  expect_error(valid_plus(sensor_text("jib", "line1", 224, 1)), 15, "sensor[1].unit_id",
               "unit id 1 is already used by sensor \"boom\" (line 4)");
}

TEST_CASE("config: two sensors cannot share an address on one bus, but may on two") {
  expect_error(valid_plus(sensor_text("jib", "line1", 223, 2)), 14, "sensor[1].address",
               "223 is already used on bus \"line1\" by sensor \"boom\" (line 4)");
  loads(valid_plus(sensor_text("jib", "line2", 223, 2) +
                   "[[bus]]\nname = \"line2\"\nport = \"/dev/ttyUSB1\"\n"));
}

TEST_CASE("config: a sensor on an unknown bus lists the buses there are") {
  expect_error(valid_plus(sensor_text("jib", "line9", 224, 2)), 12, "sensor[1].bus",
               "unknown bus \"line9\", expected one of: line1");
  expect_error(sensor_text("a", "x", 1, 1), 3, "sensor[0].bus",
               "unknown bus \"x\": no [[bus]] is defined");
}

TEST_CASE("config: two buses cannot open one tty") {
  expect_error(valid_plus("[[bus]]\nname = \"line2\"\nport = \"/dev/ttyUSB0\"\n"), 12,
               "bus[1].port", "\"/dev/ttyUSB0\" is already used by bus \"line1\" (line 1)");
  // Two spellings of one existing device compare by their canonical path.
  std::string text = valid_plus("[[bus]]\nname = \"line2\"\nport = \"/dev/../dev/null\"\n");
  text.replace(text.find("/dev/ttyUSB0"), 12, "/dev/null");
  expect_error(text, 12, "bus[1].port",
               "\"/dev/../dev/null\" is /dev/null, the same device as the port \"/dev/null\" of "
               "bus \"line1\" (line 1)");
}
