// What a reload keeps, replaces, adds and removes (gateway/config_diff.h): two loaded files,
// compared by name, where a setting was declared left out.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "gateway/config_diff.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

using Names = std::vector<std::string>;

constexpr std::string_view kTwoBuses = R"([[bus]]
name = "line1"
port = "/dev/ttyUSB0"
[[bus]]
name = "line2"
port = "/dev/ttyUSB1"
)";

std::string two_buses_plus(std::string_view sensors) {
  return std::string(kTwoBuses) + std::string(sensors);
}

const std::string kBoomAndArm =
    sensor_text("boom", "line1", 223, 1) + sensor_text("arm", "line1", 101, 2);

}  // namespace

TEST_CASE("config diff: the same file keeps every bus and sensor") {
  const Config config = loads(two_buses_plus(kBoomAndArm));
  const ConfigDiff diff = diff_configs(config, config);
  CHECK(diff.buses_kept == Names{"line1", "line2"});
  CHECK(diff.sensors_kept == Names{"boom", "arm"});
  CHECK(diff.buses_unchanged());
  CHECK(diff.sensors_unchanged());
  CHECK_FALSE(diff.server_changed);
  CHECK_FALSE(diff.http_changed);
  CHECK_FALSE(diff.mqtt_changed);
}

TEST_CASE("config diff: where a bus or sensor was declared does not count") {
  // Comment lines move every table down the file; nothing else changes.
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads("# moved\n# down\n" + two_buses_plus(kBoomAndArm));
  REQUIRE(after.sensors[0].line != before.sensors[0].line);
  REQUIRE(after.buses[0].line != before.buses[0].line);
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.buses_kept == Names{"line1", "line2"});
  CHECK(diff.sensors_kept == Names{"boom", "arm"});
}

TEST_CASE("config diff: a sensor with a changed setting is changed, the others kept") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads(two_buses_plus(sensor_text("boom", "line1", 223, 1) +
                                            sensor_text("arm", "line1", 101, 2) +
                                            "poll_ms = 250\n"));
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.sensors_kept == Names{"boom"});
  CHECK(diff.sensors_changed == Names{"arm"});
  CHECK(diff.sensors_added.empty());
  CHECK(diff.sensors_removed.empty());
  CHECK(diff.buses_unchanged());
}

TEST_CASE("config diff: a new unit id or map changes the sensor") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config new_unit = loads(two_buses_plus(sensor_text("boom", "line1", 223, 7) +
                                               sensor_text("arm", "line1", 101, 2)));
  CHECK(diff_configs(before, new_unit).sensors_changed == Names{"boom"});
  const Config new_map = loads(two_buses_plus(
      sensor_text("boom", "line1", 223, 1) + sensor_text("arm", "line1", 101, 2) +
      "[sensor.map]\nextends = \"default\"\nremove = [\"status\"]\n"));
  CHECK(diff_configs(before, new_map).sensors_changed == Names{"arm"});
}

TEST_CASE("config diff: a renamed sensor is one removed and one added") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads(two_buses_plus(sensor_text("boom", "line1", 223, 1) +
                                            sensor_text("stick", "line1", 101, 2)));
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.sensors_kept == Names{"boom"});
  CHECK(diff.sensors_removed == Names{"arm"});
  CHECK(diff.sensors_added == Names{"stick"});
  CHECK(diff.sensors_changed.empty());
}

TEST_CASE("config diff: a sensor moved to another bus is changed") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads(two_buses_plus(sensor_text("boom", "line1", 223, 1) +
                                            sensor_text("arm", "line2", 101, 2)));
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.sensors_changed == Names{"arm"});
  CHECK(diff.sensors_kept == Names{"boom"});
}

TEST_CASE("config diff: a bus given a tcp_port keeps its tty and its sensors") {
  // Which port serves its units is routing: the gateway routes every unit anew at a reload.
  const Config before = loads(two_buses_plus(kBoomAndArm));
  std::string text = two_buses_plus(kBoomAndArm);
  text.insert(text.find("[[bus]]\nname = \"line2\""), "tcp_port = 5021\n");
  const Config after = loads(text);
  REQUIRE(after.buses[0].tcp_port == 5021);
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.buses_kept == Names{"line1", "line2"});
  CHECK(diff.sensors_kept == Names{"boom", "arm"});
}

TEST_CASE("config diff: a changed bus is reopened and its sensors are replaced") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  std::string text = two_buses_plus(kBoomAndArm);
  text.replace(text.find("/dev/ttyUSB0"), 12, "/dev/ttyUSB9");
  const ConfigDiff diff = diff_configs(before, loads(text));
  CHECK(diff.buses_reopened == Names{"line1"});
  CHECK(diff.buses_kept == Names{"line2"});
  CHECK(diff.sensors_changed == Names{"boom", "arm"});
  CHECK(diff.sensors_kept.empty());
}

TEST_CASE("config diff: removed and added buses and sensors") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads(
      "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n[[bus]]\nname = \"line3\"\n"
      "port = \"/dev/ttyUSB3\"\n" +
      sensor_text("boom", "line1", 223, 1) + sensor_text("mast", "line3", 5, 9));
  const ConfigDiff diff = diff_configs(before, after);
  CHECK(diff.buses_kept == Names{"line1"});
  CHECK(diff.buses_added == Names{"line3"});
  CHECK(diff.buses_removed == Names{"line2"});
  CHECK(diff.sensors_kept == Names{"boom"});
  CHECK(diff.sensors_added == Names{"mast"});
  CHECK(diff.sensors_removed == Names{"arm"});
}

TEST_CASE("config diff: server, http and mqtt sections are compared as a whole") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const ConfigDiff timeouts =
      diff_configs(before, loads("[server]\nwrite_timeout_ms = 900\n" + two_buses_plus(kBoomAndArm)));
  CHECK(timeouts.server_changed);
  CHECK_FALSE(timeouts.server_listener_changed);
  CHECK_FALSE(timeouts.control_socket_changed);
  const ConfigDiff port =
      diff_configs(before, loads("[server]\nport = 1502\n" + two_buses_plus(kBoomAndArm)));
  CHECK(port.server_listener_changed);
  const ConfigDiff http =
      diff_configs(before, loads("[http]\nport = 8081\n" + two_buses_plus(kBoomAndArm)));
  CHECK(http.http_changed);
  CHECK_FALSE(http.server_changed);
  CHECK_FALSE(http.mqtt_changed);
}

TEST_CASE("config diff: the summary names every bus and sensor by what happens to it") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads(two_buses_plus(sensor_text("boom", "line1", 223, 1) +
                                            sensor_text("stick", "line1", 101, 2)));
  CHECK(summarize(diff_configs(before, after)) ==
        "buses kept: line1, line2; reopened: -; added: -; removed: -. sensors kept: boom; "
        "changed: -; added: stick; removed: arm");
}

TEST_CASE("config diff: an apply's audit text names the sections changed and a door that moved") {
  const Config before = loads(two_buses_plus(kBoomAndArm));
  const Config after = loads("[http]\nlisten = \"0.0.0.0\"\nport = 8081\n[server]\nwrites = true\n" +
                             two_buses_plus(sensor_text("boom", "line1", 223, 1)));
  const std::string text = describe_changes(before, after);
  CHECK(text.find("sensors kept: boom; changed: -; added: -; removed: arm") != std::string::npos);
  CHECK(text.find("sections changed: server, http") != std::string::npos);
  CHECK(text.find("[http] 127.0.0.1:8080 -> 0.0.0.0:8081") != std::string::npos);
  CHECK(text.find("[server]") == std::string::npos);  // its address did not move
  CHECK(describe_changes(before, before).find("sections changed: -") != std::string::npos);
}
