// The configuration loader: the example loads, defaults hold, and each kind of mistake is
// reported at its line, under its key, saying what is expected.
#include <doctest/doctest.h>

#include <string>
#include <string_view>

#include "config/config_loader.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

std::string joined(const ConfigErrors& errors) {
  std::string out;
  for (const ConfigError& e : errors) out += e.to_string() + "\n";
  return out;
}

ConfigErrors errors_of(std::string_view text) {
  auto loaded = load_config_string(text, "test.toml");
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error();
}

// The one error `text` holds.
ConfigError only_error(std::string_view text) {
  const ConfigErrors errors = errors_of(text);
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  return errors[0];
}

Config loads(std::string_view text) {
  auto loaded = load_config_string(text, "test.toml");
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  return *loaded;
}

// Lines 1..8: one Rieker bus and one sensor, valid. Tests append from line 9 on.
constexpr std::string_view kValid = R"([[bus]]
name = "line1"
port = "/dev/ttyUSB0"
[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
)";

std::string valid_plus(std::string_view rest) {
  return std::string(kValid) + "unit_id = 1\n" + std::string(rest);
}

// A [[sensor]] table of 6 lines: header, name, bus, model "h6", address, unit_id.
std::string sensor_text(std::string_view name, std::string_view bus, int address, int unit_id) {
  return "[[sensor]]\nname = \"" + std::string(name) + "\"\nbus = \"" + std::string(bus) +
         "\"\nmodel = \"h6\"\naddress = " + std::to_string(address) +
         "\nunit_id = " + std::to_string(unit_id) + "\n";
}

// Lines 1..4 and then `more`: a Spectron bus "s".
std::string dyna_bus(std::string_view protocol, std::string_view more) {
  return "[[bus]]\nname = \"s\"\nport = \"/dev/ttyS1\"\nprotocol = \"" + std::string(protocol) +
         "\"\n" + std::string(more);
}

// A Dyna on bus "s", unit 1; its address is the 5th line.
std::string dyna_sensor(int address) {
  return "[[sensor]]\nname = \"d\"\nbus = \"s\"\nmodel = \"dyna\"\naddress = " +
         std::to_string(address) + "\nunit_id = 1\n";
}

// `text` holds exactly one error: at `line`, under `key`, saying `message`.
void expect_error(const std::string& text, int line, std::string_view key,
                  std::string_view message) {
  CAPTURE(text);
  const ConfigError e = only_error(text);
  CHECK(e.line == line);
  CHECK(e.key == key);
  CHECK(e.message == message);
}

// The valid text with `keys` added to its bus from line 4 on.
std::string with_bus_keys(std::string_view keys) {
  std::string text = valid_plus("");
  return text.insert(text.find("[[sensor]]"), keys);
}

}  // namespace

TEST_CASE("config: the example file loads") {
  auto loaded = load_config_file(TILTGATE_SOURCE_DIR "/examples/tiltgate.toml");
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
  auto loaded = load_config_string(text, "plant.toml");
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
      "counts_per_degree, zero_counts, eeprom_reserved_writes, device, mounting, alarms, offline, "
      "substitute, map");
}

TEST_CASE("config: an unknown table is rejected, with a suggestion when one is close") {
  expect_error(valid_plus("[sensors]\nx = 1\n"), 10, "sensors",
               "unknown table; did you mean [[sensor]]?");
  expect_error(valid_plus("[logging]\nlevel = 1\n"), 10, "logging",
               "unknown table; expected the tables [server], [[bus]] and [[sensor]]");
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
  CHECK(errors[0].message == "required key is missing; expected \"h6\", \"h4360\", \"dyna\" or \"modbus-rtu\"");
  CHECK(errors[1].key == "sensor[1].address");
  CHECK(errors[1].message == "required key is missing; expected an integer");
  CHECK(errors[2].key == "sensor[1].unit_id");
  CHECK(errors[2].message == "required key is missing; expected an integer in 1..247");
}

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

TEST_CASE("config: a model must suit its bus protocol") {
  std::string dyna_on_rieker = valid_plus("");
  dyna_on_rieker.replace(dyna_on_rieker.find("\"h6\""), 4, "\"dyna\"");
  expect_error(dyna_on_rieker, 7, "sensor[0].model",
               "model \"dyna\" needs a spectron-9bit or spectron-modbus bus, but bus \"line1\" is "
               "rieker");
  expect_error(with_bus_keys("protocol = \"spectron-modbus\"\nbaud = 28800\n"), 9,
               "sensor[0].model",
               "model \"h6\" needs a rieker bus, but bus \"line1\" is spectron-modbus");
}

TEST_CASE("config: the baud rate must be one the protocol's sensors support") {
  expect_error(with_bus_keys("baud = 57600\n"), 4, "bus[0].baud",
               "57600 is not a rieker baud rate, expected one of 9600, 19200, 38400, 62500, "
               "115200, 125000, 128000, 250000");
  expect_error(dyna_bus("spectron-9bit", "baud = 125000\n") + dyna_sensor(1), 5, "bus[0].baud",
               "125000 is not a spectron-9bit baud rate, expected one of 4800, 9600, 19200, "
               "28800, 38400");
  expect_error(dyna_bus("spectron-9bit", "") + dyna_sensor(1), 1, "bus[0].baud",
               "required key is missing on spectron-9bit buses; expected one of 4800, 9600, "
               "19200, 28800, 38400");
}

TEST_CASE("config: sensor addresses follow the bus protocol's range") {
  const auto rieker_with = [](std::string_view address) {
    std::string text = valid_plus("");
    return text.replace(text.find("address = 223"), 13, "address = " + std::string(address));
  };
  expect_error(rieker_with("0"), 8, "sensor[0].address",
               "0 is out of range for a rieker bus, expected 1..65000");
  expect_error(rieker_with("65001"), 8, "sensor[0].address",
               "65001 is out of range for a rieker bus, expected 1..65000");
  expect_error(with_bus_keys("master_address = 223\n"), 9, "sensor[0].address",
               "223 is the master_address of bus \"line1\"; a sensor needs an address of its own");
  const std::string baud = "baud = 28800\n";
  loads(dyna_bus("spectron-9bit", baud) + dyna_sensor(0));
  loads(dyna_bus("spectron-modbus", baud) + dyna_sensor(250));
  expect_error(dyna_bus("spectron-9bit", baud) + dyna_sensor(256), 10, "sensor[0].address",
               "256 is out of range for a spectron-9bit bus, expected 0..255");
  expect_error(dyna_bus("spectron-modbus", baud) + dyna_sensor(0), 10, "sensor[0].address",
               "0 is out of range for a spectron-modbus bus, expected 1..250");
  expect_error(dyna_bus("spectron-modbus", baud) + dyna_sensor(251), 10, "sensor[0].address",
               "251 is out of range for a spectron-modbus bus, expected 1..250");
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

TEST_CASE("config: Dyna scaling takes integers or floats, and only on a Dyna") {
  const std::string dyna = dyna_bus("spectron-modbus", "baud = 9600\n") + dyna_sensor(1);
  const Config as_int = loads(dyna + "counts_per_degree = 200\nzero_counts = -5\n");
  CHECK(as_int.sensors[0].family_options.get("counts_per_degree", 0) == 200.0);
  CHECK(as_int.sensors[0].family_options.get("zero_counts", 0) == -5.0);
  CHECK(loads(dyna + "counts_per_degree = 12.5\n")
            .sensors[0]
            .family_options.get("counts_per_degree", 0) == 12.5);
  expect_error(dyna + "counts_per_degree = 0\n", 12, "sensor[0].counts_per_degree",
               "must not be 0 (raw counts are divided by it)");
  expect_error(valid_plus("zero_counts = 3\n"), 10, "sensor[0].zero_counts",
               "applies to model \"dyna\" only, not \"h6\"");
}

TEST_CASE("config: eeprom_reserved_writes is off by default, a boolean, and Dyna only") {
  const std::string dyna = dyna_bus("spectron-modbus", "baud = 9600\n") + dyna_sensor(1);
  CHECK_FALSE(loads(dyna).sensors[0].family_options.flag("eeprom_reserved_writes"));
  CHECK(loads(dyna + "eeprom_reserved_writes = true\n")
            .sensors[0]
            .family_options.flag("eeprom_reserved_writes"));
  expect_error(valid_plus("eeprom_reserved_writes = true\n"), 10,
               "sensor[0].eeprom_reserved_writes", "applies to model \"dyna\" only, not \"h6\"");
}

TEST_CASE("config: stale_ms shorter than poll_ms is an error") {
  expect_error(valid_plus("poll_ms = 500\nstale_ms = 200\n"), 11, "sensor[0].stale_ms",
               "200 is less than poll_ms 500: every reading would be stale before the next poll");
}

TEST_CASE("config: bus settings that contradict each other or the protocol") {
  expect_error(with_bus_keys("reopen_min_ms = 5000\nreopen_max_ms = 1000\n"), 5,
               "bus[0].reopen_max_ms", "reopen_max_ms 1000 is less than reopen_min_ms 5000");
  expect_error(with_bus_keys("gap_us = 200\n"), 4, "bus[0].gap_us",
               "200 is too short for rieker sensors, expected 1000..1000000");
  expect_error(dyna_bus("spectron-9bit", "baud = 9600\nmaster_address = 5\n") + dyna_sensor(1), 6,
               "bus[0].master_address", "applies to rieker buses only, not spectron-9bit");
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
  CHECK(errors[3].message == "\"h7\" is not valid, expected \"h6\", \"h4360\", \"dyna\" or \"modbus-rtu\"");
}

TEST_CASE("config: a file that cannot be opened says why") {
  auto loaded = load_config_file("/nonexistent/tiltgate.toml");
  REQUIRE_FALSE(loaded.has_value());
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].to_string() ==
        "/nonexistent/tiltgate.toml: cannot open: No such file or directory");
}

TEST_CASE("config: max_timeout_ms below timeout_ms is an error that says what is expected") {
  expect_error(with_bus_keys("timeout_ms = 100\nmax_timeout_ms = 80\n"), 5,
               "bus[0].max_timeout_ms", "80 is less than timeout_ms 100, expected at least 100");
}

TEST_CASE("config: the late guard's default follows the time-outs, and can be set") {
  const Config longer = loads(with_bus_keys("timeout_ms = 100\nmax_timeout_ms = 1000\n"));
  CHECK(longer.buses.at(0).max_timeout == 1000ms);
  CHECK(longer.buses.at(0).late_guard == 900ms);
  // A time-out above the default maximum raises the maximum with it; the guard keeps its floor.
  const Config slow = loads(with_bus_keys("timeout_ms = 800\n"));
  CHECK(slow.buses.at(0).max_timeout == 800ms);
  CHECK(slow.buses.at(0).late_guard == kMinDefaultLateGuard);
  const Config set = loads(with_bus_keys("late_guard_ms = 250\n"));
  CHECK(set.buses.at(0).late_guard == 250ms);
}
