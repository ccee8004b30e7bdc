// [[bus]] low_latency: on unless a bus turns it off, a boolean checked at its line, and a
// change reopens the bus (its tty gets the new setting only at an open).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "gateway/config_diff.h"
#include "gateway/serial_options.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("config: a bus sets the low-latency flag unless it says low_latency = false") {
  CHECK(loads(valid_plus("")).buses.at(0).low_latency);
  CHECK(loads(with_bus_keys("low_latency = true\n")).buses.at(0).low_latency);
  const Config off = loads(with_bus_keys("low_latency = false\n"));
  CHECK_FALSE(off.buses.at(0).low_latency);
  CHECK_FALSE(serial_options_from(registered_families(), off.buses.at(0)).low_latency);
  CHECK(serial_options_from(registered_families(), loads(valid_plus("")).buses.at(0)).low_latency);
}

TEST_CASE("config: low_latency must be a boolean") {
  expect_error(with_bus_keys("low_latency = 1\n"), 4, "bus[0].low_latency",
               "expected a boolean, got an integer");
  expect_error(with_bus_keys("\nlow_latency = \"yes\"\n"), 5, "bus[0].low_latency",
               "expected a boolean, got a string");
}

TEST_CASE("config diff: a bus whose low_latency changed is reopened") {
  const Config before = loads(valid_plus(""));
  const ConfigDiff diff = diff_configs(before, loads(with_bus_keys("low_latency = false\n")));
  CHECK(diff.buses_reopened == std::vector<std::string>{"line1"});
  CHECK(diff.buses_kept.empty());
}
