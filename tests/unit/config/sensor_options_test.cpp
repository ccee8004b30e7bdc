// [[sensor]] mounting, alarms, offline reads and serial: as inline tables or [sensor.x] sub-tables,
// with their ranges and the keys a single-axis model cannot use.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <string_view>

#include "config/config_loader.h"

using namespace tiltgate;

namespace {

std::string joined(const ConfigErrors& errors) {
  std::string out;
  for (const ConfigError& e : errors) out += e.to_string() + "\n";
  return out;
}

// Lines 1..9: a bus and a sensor of `model`; `rest` starts at line 10.
std::string sensor_with(std::string_view rest, std::string_view model = "h6") {
  return "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n[[sensor]]\nname = \"s\"\n"
         "bus = \"line1\"\nmodel = \"" +
         std::string(model) + "\"\naddress = 223\nunit_id = 1\n" + std::string(rest);
}

SensorConfig loads(const std::string& text) {
  auto loaded = load_config_string(text, "test.toml", registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  return loaded->sensors.at(0);
}

void expect_error(const std::string& text, int line, std::string_view key,
                  std::string_view message) {
  auto loaded = load_config_string(text, "test.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  INFO(joined(loaded.error()));
  REQUIRE(loaded.error().size() == 1);
  const ConfigError& e = loaded.error()[0];
  CHECK(e.line == line);
  CHECK(e.key == key);
  CHECK(e.message == message);
}

}  // namespace

TEST_CASE("sensor options: mounting as an inline table") {
  const SensorConfig s = loads(sensor_with(
      "mounting = { swap_axes = true, invert_x = false, invert_y = true, rotate_deg = 12.5 }\n"));
  CHECK(s.mounting.swap_axes);
  CHECK_FALSE(s.mounting.invert_x);
  CHECK(s.mounting.invert_y);
  CHECK(s.mounting.rotate_deg == 12.5);
}

TEST_CASE("sensor options: mounting and alarms as [sensor.x] sub-tables") {
  const SensorConfig s = loads(sensor_with(
      "[sensor.mounting]\nrotate_deg = -90\n[sensor.alarms]\nx_high = 5\nx_low = -5.0\n"));
  CHECK(s.mounting.rotate_deg == -90.0);
  CHECK(s.alarms.x_high == 5.0);
  CHECK(s.alarms.x_low == -5.0);
  CHECK_FALSE(s.alarms.y_high.has_value());
}

TEST_CASE("sensor options: every alarm key") {
  const SensorConfig s = loads(sensor_with(
      "alarms = { x_high = 5.0, x_low = -5.0, y_high = 4.0, y_low = -4.0, tilt_high = 8.0, "
      "hysteresis_deg = 0.25, rate_limit_deg_s = 2.0 }\n"));
  CHECK(s.alarms.y_high == 4.0);
  CHECK(s.alarms.y_low == -4.0);
  CHECK(s.alarms.tilt_high == 8.0);
  CHECK(s.alarms.hysteresis_deg == 0.25);
  CHECK(s.alarms.rate_limit_deg_s == 2.0);
  CHECK(loads(sensor_with("")).alarms.hysteresis_deg == 0.5);  // the default
}

TEST_CASE("sensor options: ranges and order of mounting and alarm values") {
  expect_error(sensor_with("mounting = { rotate_deg = 400 }\n"), 10,
               "sensor[0].mounting.rotate_deg", "400 is out of range, expected -360..360");
  expect_error(sensor_with("alarms = { hysteresis_deg = -0.1 }\n"), 10,
               "sensor[0].alarms.hysteresis_deg", "-0.1 is out of range, expected 0..180");
  expect_error(sensor_with("alarms = { x_low = 5.0, x_high = -5.0 }\n"), 10,
               "sensor[0].alarms.x_low", "x_low 5 is not below x_high -5");
  expect_error(sensor_with("alarms = { rate_limit_deg_s = 0 }\n"), 10,
               "sensor[0].alarms.rate_limit_deg_s", "0 is not above 0 degrees per second");
  expect_error(sensor_with("alarms = { x_high = 200 }\n"), 10, "sensor[0].alarms.x_high",
               "200 is out of range, expected -180..180");
  expect_error(sensor_with("mounting = { swap = true }\n"), 10, "sensor[0].mounting.swap",
               "unknown key; did you mean \"swap_axes\"?");
  expect_error(sensor_with("mounting = 3\n"), 10, "sensor[0].mounting",
               "expected a table, got an integer");
}

TEST_CASE("sensor options: a single-axis model takes no second-axis settings") {
  const std::string expected = "needs two axes; model \"h4360\" has one";
  expect_error(sensor_with("mounting = { swap_axes = true }\n", "h4360"), 10,
               "sensor[0].mounting.swap_axes", expected);
  expect_error(sensor_with("mounting = { rotate_deg = 5 }\n", "h4360"), 10,
               "sensor[0].mounting.rotate_deg", expected);
  expect_error(sensor_with("alarms = { y_high = 5 }\n", "h4360"), 10, "sensor[0].alarms.y_high",
               expected);
  const SensorConfig s =
      loads(sensor_with("mounting = { invert_x = true }\nalarms = { tilt_high = 3 }\n", "h4360"));
  CHECK(s.mounting.invert_x);
  CHECK(s.alarms.tilt_high == 3.0);
}

TEST_CASE("sensor options: what an offline sensor's measurements read as") {
  CHECK(loads(sensor_with("")).offline == OfflineRead::exception);
  CHECK(loads(sensor_with("offline = \"last\"\n")).offline == OfflineRead::last_value);
  const SensorConfig s = loads(sensor_with("offline = \"substitute\"\nsubstitute = -32768\n"));
  CHECK(s.offline == OfflineRead::substitute);
  CHECK(s.substitute == -32768.0);
  CHECK(std::isnan(loads(sensor_with("offline = \"substitute\"\nsubstitute = nan\n")).substitute));
  expect_error(sensor_with("substitute = 5\n"), 10, "sensor[0].substitute",
               "applies with offline = \"substitute\" only");
  expect_error(sensor_with("offline = \"zero\"\n"), 10, "sensor[0].offline",
               "\"zero\" is not valid, expected \"exception\", \"last\" or \"substitute\"");
}

TEST_CASE("sensor options: serial is the one the sensor reports, trimmed, and not empty") {
  CHECK(loads(sensor_with("")).serial.empty());
  CHECK(loads(sensor_with("serial = \" 9600223 \"\n")).serial == "9600223");
  expect_error(sensor_with("serial = \"  \"\n"), 10, "sensor[0].serial",
               "must not be empty (leave the key out instead)");
}
