// [[sensor]] alarms at two levels with for_ms, lever_m and baseline (config/alarm_options.h,
// config/sensor_options.h): read, ranged, and checked against each other at their line.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <string_view>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using test::expect_error;
using test::valid_plus;

// The valid file's sensor with `rest` from line 10 on; `model` instead of the H6.
std::string monitored_sensor(std::string_view rest, std::string_view model = "h6") {
  std::string text = valid_plus(rest);
  if (model != "h6") text.replace(text.find("\"h6\""), 4, "\"" + std::string(model) + "\"");
  return text;
}

SensorConfig monitored(const std::string& text) { return test::loads(text).sensors.at(0); }

void refused(const std::string& text, int line, std::string_view key, std::string_view message) {
  expect_error(text, line, key, message);
}

}  // namespace

TEST_CASE("alarm options: two levels, for_ms, displacement, lever_m and a baseline") {
  const SensorConfig s = monitored(monitored_sensor(
      "lever_m = 12.5\nbaseline = { x = 0.25, y = -0.5 }\n"
      "[sensor.alarms]\nx_high = 2.0\nx_low = -2\ndisplacement_high_mm = 20\nfor_ms = 5000\n"
      "hysteresis_mm = 1.5\n[sensor.alarms.danger]\nx_high = 4\ndisplacement_high_mm = 40\n"));
  CHECK(s.lever_m == 12.5);
  REQUIRE(s.baseline.has_value());
  CHECK(s.baseline->x == 0.25);
  CHECK(s.baseline->y == -0.5);
  CHECK(s.alarms.x_high == 2.0);
  CHECK(s.alarms.x_low == -2.0);
  CHECK(s.alarms.displacement_high_mm == 20.0);
  CHECK(s.alarms.hold == 5000ms);
  CHECK(s.alarms.hysteresis_mm == 1.5);
  CHECK(s.alarms.danger.x_high == 4.0);
  CHECK(s.alarms.danger.displacement_high_mm == 40.0);
  CHECK_FALSE(s.alarms.danger.x_low.has_value());
  const SensorConfig plain = monitored(monitored_sensor(""));
  CHECK_FALSE(plain.lever_m.has_value());
  CHECK_FALSE(plain.baseline.has_value());
  CHECK(plain.alarms.hold == 0ms);
  CHECK(plain.alarms.hysteresis_mm == 0.5);
}

TEST_CASE("alarm options: the errors, each at its line") {
  refused(monitored_sensor("alarms = { displacement_high_mm = 5 }\n"), 10,
          "sensor[0].alarms.displacement_high_mm",
          "needs the sensor's lever_m (the height the displacement is measured at)");
  refused(monitored_sensor("alarms = { for_ms = -1 }\n"), 10, "sensor[0].alarms.for_ms",
          "-1 is out of range, expected 0..86400000");
  refused(monitored_sensor("[sensor.alarms]\nx_high = 3\n[sensor.alarms.danger]\nx_high = 2\n"),
          13, "sensor[0].alarms.danger.x_high",
          "danger x_high 2 is not above the warning level's 3");
  refused(monitored_sensor("alarms = { x_low = -3, danger = { x_low = -1 } }\n"), 10,
          "sensor[0].alarms.danger.x_low", "danger x_low -1 is not below the warning level's -3");
  refused(monitored_sensor("alarms = { danger = { tilt = 5 } }\n"), 10,
          "sensor[0].alarms.danger.tilt", "unknown key; did you mean \"tilt_high\"?");
  refused(monitored_sensor("lever_m = 0\n"), 10, "sensor[0].lever_m",
          "0 is out of range, expected above 0 and at most 10000 (metres)");
  refused(monitored_sensor("baseline = { x = 200 }\n"), 10, "sensor[0].baseline.x",
          "200 is out of range, expected -180..180");
  refused(monitored_sensor("baseline = { y = 1 }\n", "h4360"), 10, "sensor[0].baseline.y",
          "needs two axes; model \"h4360\" has one");
  refused(monitored_sensor("alarms = { danger = { y_high = 5 } }\n", "h4360"), 10,
          "sensor[0].alarms.danger.y_high", "needs two axes; model \"h4360\" has one");
}
