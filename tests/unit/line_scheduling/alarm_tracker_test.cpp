// Alarm levels, for_ms, hysteresis and latches of line_scheduling/alarm_tracker, on hand-made
// values: what keeps a noisy reading from chattering, and what a PLC's acknowledgement does.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "line_scheduling/alarm_tracker.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const SteadyClock::time_point start = SteadyClock::time_point() + 1h;

AlarmValues x_of(double x) {
  AlarmValues v;
  v.x = x;
  return v;
}

// Feeds x values one per `step` and returns the warning flags after each, and every change.
struct Run {
  std::vector<std::uint16_t> warning;
  std::vector<AlarmTransition> changes;
};

Run run(const AlarmConfig& config, const std::vector<double>& xs,
        std::chrono::milliseconds step = 100ms) {
  AlarmTracker tracker(config);
  Run out;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    tracker.update(x_of(xs[i]), start + step * i, out.changes);
    out.warning.push_back(tracker.warning());
  }
  return out;
}

}  // namespace

TEST_CASE("alarm tracker: for_ms holds a set back until the value stayed past for that long") {
  AlarmConfig config;
  config.x_high = 2.0;
  config.hysteresis_deg = 0.1;
  config.hold = 300ms;
  using alarm_bit::x_high;
  // Past at 100 ms, back at 200 ms: the hold starts over. Past from 400 ms: set at 700 ms.
  const Run r = run(config, {0, 2.5, 1.0, 0, 2.5, 2.6, 2.4, 2.5, 2.5});
  CHECK(r.warning == std::vector<std::uint16_t>{0, 0, 0, 0, 0, 0, 0, x_high, x_high});
  REQUIRE(r.changes.size() == 1);
  CHECK(r.changes[0].kind == AlarmKind::x_high);
  CHECK(r.changes[0].level == AlarmLevel::warning);
  CHECK(r.changes[0].set);
  CHECK(r.changes[0].value == 2.5);
  CHECK(r.changes[0].threshold == 2.0);
  CHECK(r.changes[0].taken == start + 700ms);
}

TEST_CASE("alarm tracker: noise around the threshold never chatters with for_ms and hysteresis") {
  AlarmConfig config;
  config.x_high = 2.0;
  config.hysteresis_deg = 0.05;
  config.hold = 1000ms;
  // +-0.1 degree of noise around the threshold, every 100 ms, for a minute: no reading stays
  // past for a second, so the alarm never sets.
  std::vector<double> xs;
  for (int i = 0; i < 600; ++i) xs.push_back(2.0 + ((i * 7919) % 21 - 10) / 100.0);
  const Run r = run(config, xs);
  CHECK(r.changes.empty());
  // Without for_ms the same noise sets and clears many times: what the hold is there for.
  config.hold = 0ms;
  CHECK(run(config, xs).changes.size() > 20);
}

TEST_CASE("alarm tracker: a clear needs the value back by the hysteresis for for_ms too") {
  AlarmConfig config;
  config.x_high = 2.0;
  config.hysteresis_deg = 0.5;
  config.hold = 200ms;
  const Run r = run(config, {3, 3, 3, 1.9, 1.4, 1.4, 1.6, 1.4, 1.4, 1.4});
  using alarm_bit::x_high;
  // Set at 200 ms; 1.9 is not back by the hysteresis; 1.4 at 400 and 500 ms, then 1.6 starts
  // the clear's hold over; back from 700 ms: clear at 900 ms.
  CHECK(r.warning ==
        std::vector<std::uint16_t>{0, 0, x_high, x_high, x_high, x_high, x_high, x_high, x_high, 0});
  REQUIRE(r.changes.size() == 2);
  CHECK_FALSE(r.changes[1].set);
  CHECK(r.changes[1].taken == start + 900ms);
}

TEST_CASE("alarm tracker: the danger level is a second alarm beyond the warning") {
  AlarmConfig config;
  config.x_low = -2.0;
  config.danger.x_low = -4.0;
  config.hysteresis_deg = 0.0;
  AlarmTracker tracker(config);
  std::vector<AlarmTransition> changes;
  tracker.update(x_of(-3.0), start, changes);
  CHECK(tracker.warning() == alarm_bit::x_low);
  CHECK(tracker.danger() == 0);
  tracker.update(x_of(-5.0), start + 1s, changes);
  CHECK(tracker.warning() == alarm_bit::x_low);
  CHECK(tracker.danger() == alarm_bit::x_low);
  tracker.update(x_of(-1.0), start + 2s, changes);
  CHECK(tracker.warning() == 0);
  CHECK(tracker.danger() == 0);
  REQUIRE(changes.size() == 4);
  CHECK(changes[1].level == AlarmLevel::danger);
  CHECK(changes[1].threshold == -4.0);
  CHECK(std::string(to_string(changes[1].kind)) == "x_low");
  CHECK(std::string(to_string(changes[1].level)) == "danger");
}

TEST_CASE("alarm tracker: rate and displacement alarms, and NaN that neither sets nor clears") {
  AlarmConfig config;
  config.rate_limit_deg_s = 1.0;
  config.displacement_high_mm = 10.0;
  config.hysteresis_mm = 2.0;
  AlarmTracker tracker(config);
  std::vector<AlarmTransition> changes;
  AlarmValues v;
  v.rate = 2.0;
  v.displacement_mm = 11.0;
  tracker.update(v, start, changes);
  CHECK(tracker.warning() == (alarm_bit::rate | alarm_bit::displacement));
  v.rate = NAN;
  v.displacement_mm = 9.0;  // not back by hysteresis_mm
  tracker.update(v, start + 1s, changes);
  CHECK(tracker.warning() == (alarm_bit::rate | alarm_bit::displacement));
  v.rate = 1.0;  // exactly the limit: back (a rate has no hysteresis)
  v.displacement_mm = 7.9;
  tracker.update(v, start + 2s, changes);
  CHECK(tracker.warning() == 0);
  CHECK(std::string(to_string(AlarmKind::displacement_high)) == "displacement_high");
}

TEST_CASE("alarm tracker: a latched alarm stays until acknowledged and clear") {
  AlarmConfig config;
  config.x_high = 2.0;
  config.hysteresis_deg = 0.0;
  AlarmTracker tracker(config);
  std::vector<AlarmTransition> changes;
  using alarm_bit::x_high;
  tracker.update(x_of(3.0), start, changes);
  tracker.update(x_of(1.0), start + 1s, changes);  // clear, but latched
  CHECK(tracker.warning() == 0);
  CHECK(tracker.latched() == x_high);
  CHECK(tracker.unacknowledged() == x_high);
  tracker.acknowledge();  // clear and acknowledged: gone
  CHECK(tracker.latched() == 0);
  CHECK(tracker.unacknowledged() == 0);

  tracker.update(x_of(3.0), start + 2s, changes);
  tracker.acknowledge();  // still set: stays latched, acknowledged
  CHECK(tracker.latched() == x_high);
  CHECK(tracker.unacknowledged() == 0);
  tracker.update(x_of(1.0), start + 3s, changes);  // clears: goes, as it was acknowledged
  CHECK(tracker.latched() == 0);

  tracker.update(x_of(3.0), start + 4s, changes);
  tracker.acknowledge();
  tracker.update(x_of(1.0), start + 5s, changes);
  tracker.update(x_of(3.0), start + 6s, changes);  // sets again: a new acknowledgement is owed
  CHECK(tracker.unacknowledged() == x_high);
}
