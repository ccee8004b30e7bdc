// Checks that depend on a bus's protocol and a sensor's family: models, bauds, address ranges,
// the family's own keys, and the reply timing keys.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

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
