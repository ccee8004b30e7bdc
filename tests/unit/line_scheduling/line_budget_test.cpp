// The line's time budget (line_scheduling/line_budget.h): the worst age of a healthy sensor's reading
// while two others on its line fail, from the line's settings and sensors, and the warnings
// `tiltgate check` prints where it passes stale_ms. The numbers are those docs/operations.md
// quotes ("One failing sensor never takes its line").
#include <doctest/doctest.h>

#include <fmt/format.h>
#include <string>
#include <vector>

#include "config/config.h"
#include "driver/family.h"
#include "line_scheduling/line_budget.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

// A bus with the defaults the config loader gives a bus that says only its baud.
BusConfig bus(std::string protocol, std::uint32_t baud) {
  BusConfig b;
  b.name = "line1";
  b.protocol = std::move(protocol);
  b.baud = baud;
  b.gap = 1000us;
  return b;
}

std::vector<SensorConfig> sensors(int count, std::string_view model) {
  std::vector<SensorConfig> list;
  for (int i = 1; i <= count; ++i) {
    SensorConfig s;
    s.name = fmt::format("s{}", i);
    s.bus = "line1";
    s.model = std::string(model);
    list.push_back(s);
  }
  return list;
}

const ProtocolDescriptor& protocol(std::string_view name) {
  const ProtocolEntry entry = find_protocol(registered_families(), name);
  REQUIRE(entry.protocol != nullptr);
  return *entry.protocol;
}

}  // namespace

TEST_CASE("line budget: six H6 at 125000 baud keep a healthy reading inside a second") {
  const LineBudget budget = line_budget(bus("rieker", 125000), sensors(6, "h6"), protocol("rieker"));
  CHECK(budget.failing == 2);
  CHECK(budget.poll == 5ms);           // 27 bytes at 125000 baud, 1 ms gap, 1 ms turnaround
  CHECK(budget.others == 15ms);        // the three other healthy sensors
  CHECK(budget.failing_turn == 521ms); // its request, the window to 500 ms, 20 ms of quiet
  CHECK(budget.short_look == 71ms);    // its request, 50 ms and 20 ms
  CHECK(budget.failures == 663ms);     // one whole turn and two short looks
  REQUIRE(budget.sensors.size() == 6);
  // The line keeps up: poll_ms 100 + 15, then the failures and its own poll.
  CHECK(budget.sensors[0].worst_age == 783ms);
  CHECK(budget.sensors[0].stale_after == 1000ms);
}

TEST_CASE("line budget: ten H6 at 9600 baud keep a healthy reading inside a second") {
  const LineBudget budget = line_budget(bus("rieker", 9600), sensors(10, "h6"), protocol("rieker"));
  CHECK(budget.poll == 31ms);
  CHECK(budget.others == 217ms);  // seven others: the line cannot keep up with poll_ms 100
  CHECK(budget.failing_turn == 531ms);
  CHECK(budget.short_look == 81ms);
  CHECK(budget.sensors[0].worst_age == 941ms);
}

TEST_CASE("line budget: a 9-bit line keeps every time-out's whole window, and check says so") {
  Config config;
  config.buses = {bus("spectron-9bit", 28800)};
  config.sensors = sensors(6, "dyna");
  const LineBudget budget = line_budget(config.buses[0], config.sensors, protocol("spectron-9bit"));
  CHECK(budget.failures == 2 * budget.failing_turn);
  const auto warnings = line_budget_warnings(config, registered_families());
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("bus \"line1\": while 2 of its sensors fail at once") == 0);
  CHECK(warnings[0].find("name no sender") != std::string::npos);
  CHECK(warnings[0].find("docs/operations.md") != std::string::npos);
}

TEST_CASE("line budget: no warning where the bound is inside stale_ms, nor for a lone sensor") {
  Config config;
  config.buses = {bus("rieker", 9600)};
  config.sensors = sensors(10, "h6");
  CHECK(line_budget_warnings(config, registered_families()).empty());
  config.sensors = sensors(1, "h6");
  CHECK(line_budget(config.buses[0], config.sensors, protocol("rieker")).failing == 0);
  CHECK(line_budget_warnings(config, registered_families()).empty());
}

TEST_CASE("line budget: a longer late-reply window, or more sensors, warns on the bus") {
  Config config;
  config.buses = {bus("rieker", 9600)};
  config.buses[0].max_timeout = 800ms;
  config.buses[0].late_guard = 750ms;
  config.sensors = sensors(10, "h6");
  const auto warnings = line_budget_warnings(config, registered_families());
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("the reading of \"s1\" can get 1241 ms old, past its stale_ms (1000 ms)") !=
        std::string::npos);
}

TEST_CASE("line budget: a bus of devices that speak Modbus TCP (baud 0) counts the reply wait") {
  // No serial line, so no baud: nothing divides by it, and a poll is bounded by the reply
  // wait (timeout_ms, 50 ms by default) instead of a wire time.
  BusConfig tcp = bus("modbus-tcp", 0);
  tcp.gap = 0us;
  const LineBudget budget = line_budget(tcp, sensors(4, "modbus-tcp"), protocol("modbus-tcp"));
  CHECK(budget.poll == tcp.timeout);
  CHECK(budget.poll == 50ms);
  CHECK(budget.others == 50ms);               // the one other healthy sensor
  CHECK(budget.short_look == 70ms);           // no request wire time: 50 ms and 20 ms
  CHECK(budget.failures == budget.failing_turn + 2 * budget.short_look);
}
