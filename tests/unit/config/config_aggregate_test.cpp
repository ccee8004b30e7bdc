// [[aggregate]] and [[bus]] tcp_port: an aggregate names its sensors or a bus, points of their
// maps, and a unit id free on its listener; a bus with tcp_port gets a listener of its own,
// where unit ids need only be unique among that bus's units.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// A Rieker bus of 3 lines, then its tcp_port line when given.
std::string rieker_bus(std::string_view name, std::string_view tty, int tcp_port = 0) {
  std::string text = "[[bus]]\nname = \"" + std::string(name) + "\"\nport = \"" +
                     std::string(tty) + "\"\n";
  if (tcp_port != 0) text += "tcp_port = " + std::to_string(tcp_port) + "\n";
  return text;
}

// Lines 1..15: bus "line1" (3 lines), sensors "s1" (unit 1), "s2" (unit 2) on it (lines
// 4..9, 10..15).
const std::string kTwoSensors = rieker_bus("line1", "/dev/ttyUSB0") +
                                sensor_text("s1", "line1", 1, 1) + sensor_text("s2", "line1", 2, 2);

// An [[aggregate]] from line 16: header, unit_id (17), points (18), then `rest` (19...).
std::string aggregate_text(int unit_id, std::string_view points, std::string_view rest) {
  return "[[aggregate]]\nunit_id = " + std::to_string(unit_id) + "\npoints = " +
         std::string(points) + "\n" + std::string(rest);
}

const std::string kAngles = "[\"angle_x\", \"angle_y\", \"status\"]";

// A folder with the PEM files [server] tls reads (their contents are checked only when the
// server starts), removed at the end.
struct TlsPemFiles {
  TlsPemFiles() {
    path = std::filesystem::temp_directory_path() /
           ("tiltgate-tcp-port-config-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    for (const char* name : {"gateway.pem", "gateway.key", "ca.pem"})
      std::ofstream(path / name) << "-----BEGIN " << name << "-----\n";
  }
  ~TlsPemFiles() { std::filesystem::remove_all(path); }
  // The one error of `text`, loaded as a file in the folder.
  ConfigError only_error_of(const std::string& text) const {
    auto loaded = load_config_string(text, (path / "plant.toml").string(), registered_families());
    REQUIRE_FALSE(loaded.has_value());
    INFO(joined(loaded.error()));
    REQUIRE(loaded.error().size() == 1);
    return loaded.error()[0];
  }
  std::filesystem::path path;
};

}  // namespace

TEST_CASE("config: an aggregate lists its sensors in block order") {
  const Config config =
      loads(kTwoSensors + aggregate_text(200, kAngles, "sensors = [\"s2\", \"s1\"]\n"));
  REQUIRE(config.aggregates.size() == 1);
  const AggregateConfig& aggregate = config.aggregates[0];
  CHECK(aggregate.unit_id == 200);
  CHECK(aggregate.points == std::vector<std::string>{"angle_x", "angle_y", "status"});
  CHECK(aggregate.sensors == std::vector<std::string>{"s2", "s1"});
  CHECK(aggregate.bus.empty());
  CHECK(aggregate.line == 16);
}

TEST_CASE("config: an aggregate of a bus serves its sensors in the order of the file") {
  const Config config = loads(kTwoSensors + rieker_bus("line2", "/dev/ttyUSB1") +
                              sensor_text("t1", "line2", 1, 3) +
                              aggregate_text(200, kAngles, "bus = \"line1\"\n"));
  REQUIRE(config.aggregates.size() == 1);
  CHECK(config.aggregates[0].sensors == std::vector<std::string>{"s1", "s2"});
  CHECK(config.aggregates[0].bus == "line1");
  CHECK(listener_of(config, config.aggregates[0]) == kMainListener);
}

TEST_CASE("config: an aggregate's unit id is 1..247 and free among the units of its listener") {
  expect_error(kTwoSensors + aggregate_text(0, kAngles, "bus = \"line1\"\n"), 17,
               "aggregate[0].unit_id", "0 is out of range, expected 1..247");
  expect_error(kTwoSensors + aggregate_text(248, kAngles, "bus = \"line1\"\n"), 17,
               "aggregate[0].unit_id", "248 is out of range, expected 1..247");
  expect_error(kTwoSensors + aggregate_text(2, kAngles, "bus = \"line1\"\n"), 17,
               "aggregate[0].unit_id",
               "unit id 2 is already used by sensor \"s2\" (line 10)");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "bus = \"line1\"\n") +
                   aggregate_text(200, "[\"status\"]", "sensors = [\"s1\"]\n"),
               21, "aggregate[1].unit_id",
               "unit id 200 is already used by the aggregate at line 16");
  // A unit id passed through on a bus of the same listener.
  expect_error(kTwoSensors +
                   "[[bus]]\nname = \"rtu\"\nport = \"/dev/ttyUSB5\"\nprotocol = \"modbus-rtu\"\n"
                   "pass_through = [30]\n" +
                   aggregate_text(30, kAngles, "bus = \"line1\"\n"),
               22, "aggregate[0].unit_id",
               "unit id 30 is passed through on bus \"rtu\" (line 16)");
}

TEST_CASE("config: an aggregate names known sensors or a known bus, not both, each once") {
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "sensors = [\"s1\", \"nope\", \"s9\"]\n"),
               19, "aggregate[0].sensors", "unknown sensors \"nope\", \"s9\"");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "bus = \"line9\"\n"), 19,
               "aggregate[0].bus", "unknown bus \"line9\"");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "sensors = [\"s1\"]\nbus = \"line1\"\n"),
               20, "aggregate[0].bus", "both sensors and bus are given, expected one of them");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, ""), 16, "aggregate[0].sensors",
               "required: the sensors to serve (sensors = [\"s1\", \"s2\"]), or a bus whose "
               "sensors it serves (bus = \"line1\")");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "sensors = [\"s1\", \"s2\", \"s1\"]\n"),
               19, "aggregate[0].sensors", "sensor \"s1\" is listed twice");
  expect_error(kTwoSensors + aggregate_text(200, kAngles, "sensors = []\n"), 19,
               "aggregate[0].sensors", "empty, expected at least one sensor name");
}

TEST_CASE("config: an aggregate's points exist, the same in every sensor's map") {
  expect_error(kTwoSensors + aggregate_text(200, "[]", "bus = \"line1\"\n"), 18,
               "aggregate[0].points",
               "empty, expected point names of the sensors' maps, e.g. [\"angle_x\", "
               "\"angle_y\", \"status\"]");
  expect_error(kTwoSensors + aggregate_text(200, "[\"angle_x\", \"angle_q\"]", "bus = \"line1\"\n"),
               18, "aggregate[0].points", "sensor \"s1\": its map has no point \"angle_q\"");
  expect_error(kTwoSensors + aggregate_text(200, "[\"status\", \"status\"]", "bus = \"line1\"\n"),
               18, "aggregate[0].points", "point \"status\" is listed twice");
  // s3's own map shows angle_x as int16 hundredths: not the float32 of s1's.
  const std::string narrower =
      sensor_text("s3", "line1", 3, 3) +
      "[sensor.map]\n[[sensor.map.point]]\nname = \"angle_x\"\ntable = \"input\"\naddress = 0\n"
      "type = \"int16\"\nsource = \"angle_x\"\nscale = 100\nsaturate = true\n";
  expect_error(kTwoSensors + narrower +
                   aggregate_text(200, "[\"angle_x\"]", "sensors = [\"s1\", \"s3\"]\n"),
               33, "aggregate[0].points",
               "sensor \"s3\": point \"angle_x\" is int16 (1 register) here but float32 (2 "
               "registers) in sensor \"s1\"; an aggregate's point must be the same in every "
               "sensor's map");
}

TEST_CASE("config: a bus's tcp_port gives its units a listener of their own") {
  // The same unit id on two buses of different ports; an aggregate of a bus on its port.
  const Config config =
      loads(rieker_bus("line1", "/dev/ttyUSB0", 5021) + sensor_text("a", "line1", 1, 1) +
            rieker_bus("line2", "/dev/ttyUSB1", 5022) + sensor_text("b", "line2", 1, 1) +
            sensor_text("c", "line2", 2, 2) + aggregate_text(2, kAngles, "bus = \"line1\"\n"));
  REQUIRE(config.buses.size() == 2);
  CHECK(config.buses[0].tcp_port == 5021);
  CHECK(listener_of(config.buses[1]) == 5022);
  CHECK(listener_of(config, config.sensors[1]) == 5022);
  CHECK(listener_of(config, config.aggregates[0]) == 5021);
  CHECK_FALSE(loads(kTwoSensors).buses[0].tcp_port.has_value());
}

TEST_CASE("config: unit ids are unique per listener, the main port's included") {
  // Both buses without tcp_port: one listener.
  expect_error(rieker_bus("line1", "/dev/ttyUSB0") + sensor_text("a", "line1", 1, 1) +
                   rieker_bus("line2", "/dev/ttyUSB1") + sensor_text("b", "line2", 1, 1),
               18, "sensor[1].unit_id",
               "unit id 1 is already used by sensor \"a\" (line 4)");
  // Two sensors of a bus with its own port: named with the port.
  expect_error(rieker_bus("line1", "/dev/ttyUSB0", 5021) + sensor_text("a", "line1", 1, 1) +
                   sensor_text("b", "line1", 2, 1),
               16, "sensor[1].unit_id",
               "unit id 1 is already used by sensor \"a\" (line 5) on port 5021");
  // Two buses on one port cannot be: each listener is one bus's.
  expect_error(rieker_bus("line1", "/dev/ttyUSB0", 5021) + sensor_text("a", "line1", 1, 1) +
                   rieker_bus("line2", "/dev/ttyUSB1", 5021) + sensor_text("b", "line2", 1, 2),
               14, "bus[1].tcp_port",
               "5021 is already the tcp_port of bus \"line1\" (line 1); each bus's listener needs "
               "a port of its own");
}

TEST_CASE("config: tcp_port is 1..65535 and not [server] port") {
  expect_error(rieker_bus("line1", "/dev/ttyUSB0", 70000) + sensor_text("a", "line1", 1, 1), 4,
               "bus[0].tcp_port", "70000 is out of range, expected 1..65535");
  expect_error("[server]\nport = 5020\n" + rieker_bus("line1", "/dev/ttyUSB0", 5020) +
                   sensor_text("a", "line1", 1, 1),
               6, "bus[0].tcp_port",
               "5020 is [server] port; a bus's own port must be another one");
  expect_error(rieker_bus("line1", "/dev/ttyUSB0", 502) + sensor_text("a", "line1", 1, 1), 4,
               "bus[0].tcp_port", "502 is [server] port; a bus's own port must be another one");
}

TEST_CASE("config: tcp_port is not the TLS port, and needs plain TCP") {
  const TlsPemFiles pem;
  const std::string tls =
      "tls = { cert = \"gateway.pem\", key = \"gateway.key\", ca = \"ca.pem\", port = 802 }\n";
  const ConfigError on_tls = pem.only_error_of("[server]\n" + tls +
                                               rieker_bus("line1", "/dev/ttyUSB0", 802) +
                                               sensor_text("a", "line1", 1, 1));
  CHECK(on_tls.line == 6);
  CHECK(on_tls.message == "802 is the port of [server] tls; a bus's own port must be another one");
  const ConfigError tls_only = pem.only_error_of("[server]\nplain_tcp = false\n" + tls +
                                                 rieker_bus("line1", "/dev/ttyUSB0", 5021) +
                                                 sensor_text("a", "line1", 1, 1));
  CHECK(tls_only.key == "bus[0].tcp_port");
  CHECK(tls_only.message == "a bus's own listener is plain Modbus TCP, but [server] plain_tcp = "
                            "false (TLS only); leave tcp_port out or allow plain TCP");
}

TEST_CASE("config: an aggregate's sensors share one listener") {
  expect_error(rieker_bus("line1", "/dev/ttyUSB0", 5021) + sensor_text("a", "line1", 1, 1) +
                   rieker_bus("line2", "/dev/ttyUSB1") + sensor_text("b", "line2", 1, 1) +
                   "[[aggregate]]\nunit_id = 200\npoints = [\"status\"]\n"
                   "sensors = [\"a\", \"b\"]\n",
               23, "aggregate[0].sensors",
               "sensor \"a\" is served on port 5021 but sensor \"b\" on the main port ([server] "
               "port); an aggregate's sensors must share one listener (buses with the same "
               "tcp_port, or none)");
}
