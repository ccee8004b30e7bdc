// The configuration loader: the example loads, defaults hold, and each kind of mistake is
// reported at its line, under its key, saying what is expected.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("config: the example file loads") {
  auto loaded = load_config_file(TILTGATE_SOURCE_DIR "/examples/tiltgate.toml", registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  const Config& config = *loaded;
  CHECK(config.server.port == 502);
  CHECK_FALSE(config.server.writes);
  REQUIRE(config.buses.size() == 1);
  CHECK(config.buses[0].name == "line1");
  CHECK(config.buses[0].protocol == "rieker");
  CHECK(config.buses[0].baud == 125000);
  REQUIRE(config.sensors.size() == 3);
  CHECK(config.sensors[0].model == "h6");
  CHECK(config.sensors[1].model == "h6");
  CHECK(config.sensors[2].model == "h4360");
  CHECK(config.sensors[2].unit_id == 3);
  CHECK(config.sensors[0].stale_after == 1000ms);
  CHECK(config.sensors[1].line > config.sensors[0].line);
}

TEST_CASE("config: keys left out take their defaults") {
  const Config config = loads(valid_plus(""));
  CHECK(config.path == "test.toml");
  CHECK(config.server.listen == "0.0.0.0");
  CHECK(config.server.port == 502);
  CHECK(config.server.max_clients == 32);
  CHECK(config.server.word_order == WordOrder::big);
  CHECK_FALSE(config.server.writes);
  CHECK(config.server.idle_timeout == 60000ms);
  const BusConfig& bus = config.buses.at(0);
  CHECK(bus.protocol == "rieker");
  CHECK(bus.baud == 125000);
  CHECK(bus.timeout == 50ms);
  CHECK(bus.retries == 2);
  CHECK(bus.max_timeout == 500ms);
  CHECK(bus.late_guard == 450ms);  // replies up to max_timeout land in the guard
  CHECK(bus.gap == 1000us);
  CHECK(bus.master_address == 0);
  CHECK(bus.line == 1);
  const SensorConfig& sensor = config.sensors.at(0);
  CHECK(sensor.address == 223);
  CHECK(sensor.unit_id == 1);
  CHECK(sensor.poll == 100ms);
  CHECK_FALSE(sensor.stale_after.has_value());
  CHECK(sensor.line == 4);
}

TEST_CASE("config: an error reads FILE:LINE:COL: KEY: message") {
  std::string text = std::string(kValid) + "unit_id = 1\n";  // lines 1..9
  text +=
      "[[sensor]]\nname = \"jib\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 224\nunit_id = 2\n";
  text +=
      "[[sensor]]\nname = \"s3\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 225\nunit_id = 300\n";
  auto loaded = load_config_string(text, "plant.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].to_string() ==
        "plant.toml:21:1: sensor[2].unit_id: 300 is out of range, expected 1..247");
}

TEST_CASE("config: a TOML syntax error is one error at its line and column") {
  const ConfigError e = only_error("[server]\nport = 502\nlisten = \n");
  CHECK(e.line == 3);
  CHECK(e.column > 1);
  CHECK(e.key.empty());
  CHECK(e.file == "test.toml");
}

TEST_CASE("config: an unknown key suggests the close one") {
  expect_error(valid_plus("[[bus]]\nname = \"line2\"\nport = \"/dev/ttyUSB1\"\nbaudrate = 9600\n"),
               13, "bus[1].baudrate", "unknown key; did you mean \"baud\"?");
  expect_error(valid_plus("poll_sm = 100\n"), 10, "sensor[0].poll_sm",
               "unknown key; did you mean \"poll_ms\"?");
}

TEST_CASE("config: an unknown key with nothing close lists the known keys") {
  expect_error(
      valid_plus("colour = \"red\"\n"), 10, "sensor[0].colour",
      "unknown key; expected one of: name, bus, model, address, unit_id, poll_ms, stale_ms, "
      "serial, counts_per_degree, zero_counts, temperature_counts_per_degree, "
      "temperature_zero_counts, eeprom_reserved_writes, device, mounting, lever_m, "
      "baseline, alarms, burst_s, pre_trigger_s, burst_rate_deg_s, offline, substitute, map");
}

TEST_CASE("config: an unknown table is rejected, with a suggestion when one is close") {
  expect_error(valid_plus("[sensors]\nx = 1\n"), 10, "sensors",
               "unknown table; did you mean [[sensor]]?");
  expect_error(valid_plus("[logging]\nlevel = 1\n"), 10, "logging",
               "unknown table; expected the tables [server], [http], [mqtt], [sparkplug], [audit], "
               "[redundancy], [record], [[bus]], [[sensor]] and [[aggregate]]");
}

TEST_CASE("config: [bus] written as a single table asks for [[bus]]") {
  const ConfigErrors errors = errors_of("[bus]\nname = \"line1\"\n[[sensor]]\n");
  REQUIRE_FALSE(errors.empty());
  CHECK(errors[0].line == 1);
  CHECK(errors[0].key == "bus");
  CHECK(errors[0].message == "expected an array of tables ([[bus]]), got a table");
}

TEST_CASE("config: a value of the wrong type names both types") {
  expect_error("[server]\nport = \"502\"\n" + valid_plus(""), 2, "server.port",
               "expected an integer, got a string");
  expect_error("[server]\n\nwrites = \"yes\"\n" + valid_plus(""), 3, "server.writes",
               "expected a boolean, got a string");
  expect_error(valid_plus("poll_ms = 100.0\n"), 10, "sensor[0].poll_ms",
               "expected an integer, got a float");
}

TEST_CASE("config: values out of range give the range") {
  const std::string bus_b = "[[bus]]\nname = \"b\"\nport = \"/dev/ttyS9\"\n";
  expect_error(valid_plus("poll_ms = 5\n"), 10, "sensor[0].poll_ms",
               "5 is out of range, expected 10..3600000");
  expect_error("[server]\nport = 0\n" + valid_plus(""), 2, "server.port",
               "0 is out of range, expected 1..65535");
  expect_error("[server]\nmax_clients = 2000\n" + valid_plus(""), 2, "server.max_clients",
               "2000 is out of range, expected 1..1024");
  expect_error(bus_b + "timeout_ms = 0\n" + valid_plus(""), 4, "bus[0].timeout_ms",
               "0 is out of range, expected 1..10000");
  expect_error(bus_b + "retries = 11\n" + valid_plus(""), 4, "bus[0].retries",
               "11 is out of range, expected 0..10");
  expect_error("[server]\nword_order = \"middle\"\n" + valid_plus(""), 2, "server.word_order",
               "\"middle\" is not valid, expected \"big\" or \"little\"");
}

TEST_CASE("config: missing required keys are reported at the table header") {
  const ConfigErrors errors =
      errors_of(valid_plus("[[sensor]]\nname = \"jib\"\nbus = \"line1\"\n"));
  INFO(joined(errors));
  REQUIRE(errors.size() == 3);
  for (const ConfigError& e : errors) CHECK(e.line == 10);
  CHECK(errors[0].key == "sensor[1].model");
  CHECK(errors[0].message == "required key is missing; expected \"h6\", \"h4360\", \"dyna\", \"modbus-rtu\" or \"modbus-tcp\"");
  CHECK(errors[1].key == "sensor[1].address");
  CHECK(errors[1].message == "required key is missing; expected an integer");
  CHECK(errors[2].key == "sensor[1].unit_id");
  CHECK(errors[2].message == "required key is missing; expected an integer in 1..247");
}


TEST_CASE("config: listen must be an IPv4 or IPv6 address") {
  CHECK(loads("[server]\nlisten = \"::1\"\n" + valid_plus("")).server.listen == "::1");
  expect_error("[server]\nlisten = \"localhost\"\n" + valid_plus(""), 2, "server.listen",
               "\"localhost\" is not an IPv4 or IPv6 address, expected e.g. \"0.0.0.0\", "
               "\"127.0.0.1\" or \"::\"");
}

TEST_CASE("config: names use letters, digits, '_', '.' and '-' only") {
  const std::string expected =
      "is not a valid name, expected one or more of the letters A-Z a-z, "
      "digits 0-9, '_', '.' and '-'";
  std::string text = valid_plus("");
  text.replace(text.find("name = \"boom\""), 13, "name = \"boom 1\"");
  expect_error(text, 5, "sensor[0].name", "\"boom 1\" " + expected);
  text.replace(text.find("name = \"boom 1\""), 15, "name = \"\"");
  expect_error(text, 5, "sensor[0].name", "\"\" " + expected);
}

TEST_CASE("config: a configuration without sensors is an error") {
  const ConfigError e = only_error("[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n");
  CHECK(e.line == 0);
  CHECK(e.key == "sensor");
  CHECK(e.to_string() == "test.toml: sensor: no [[sensor]] defined, expected at least one");
}


TEST_CASE("config: every error in a file is reported, in line order") {
  const ConfigErrors errors = errors_of(
      "[server]\nport = 70000\nmax_clients = 0\n[[bus]]\nname = \"line1\"\n"
      "port = \"/dev/ttyUSB0\"\nbaudrate = 9600\n[[sensor]]\nname = \"a\"\n"
      "bus = \"line1\"\nmodel = \"h7\"\naddress = 1\nunit_id = 0\n");
  INFO(joined(errors));
  REQUIRE(errors.size() == 5);
  CHECK(errors[0].line == 2);
  CHECK(errors[1].line == 3);
  CHECK(errors[2].line == 7);
  CHECK(errors[3].line == 11);
  CHECK(errors[4].line == 13);
  CHECK(errors[3].message == "\"h7\" is not valid; did you mean \"h6\"? (expected \"h6\", \"h4360\", \"dyna\", \"modbus-rtu\" or \"modbus-tcp\")");
}

TEST_CASE("config: a misspelt value gets a suggestion, as a misspelt key does") {
  const ConfigErrors errors = errors_of(
      "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\nprotocol = \"reiker\"\n");
  INFO(joined(errors));
  REQUIRE_FALSE(errors.empty());
  CHECK(errors[0].line == 4);
  CHECK(errors[0].message.starts_with("\"reiker\" is not valid; did you mean \"rieker\"? (expected "));
}

TEST_CASE("config: a file that cannot be opened says why") {
  auto loaded = load_config_file("/nonexistent/tiltgate.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].to_string() ==
        "/nonexistent/tiltgate.toml: cannot open: No such file or directory");
}

TEST_CASE("config: [server] threads is read, 1..64, left out it is 0, one per core") {
  CHECK(loads(valid_plus("")).server.threads == 0);
  CHECK(loads("[server]\nthreads = 3\n" + valid_plus("")).server.threads == 3);
  expect_error("[server]\nthreads = 0\n" + valid_plus(""), 2, "server.threads",
               "0 is out of range, expected 1..64");
  expect_error("[server]\nthreads = \"2\"\n" + valid_plus(""), 2, "server.threads",
               "expected an integer, got a string");
}
