// Each sensor's failures over the last 10 minutes, and a bus's as the sum of its sensors'.
#include <doctest/doctest.h>

#include "gateway/recent_failures.h"
#include "gateway/status_copy.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const CounterRates::Clock::time_point t0{};

FailureCounts late(std::uint64_t n) { return FailureCounts{0, 0, 0, 0, n}; }

}  // namespace

TEST_CASE("recent failures: one old late reply is gone from the window after 10 minutes") {
  RecentFailures recent;
  CHECK_FALSE(recent.of("boom", late(0)));  // not sampled yet
  recent.record("boom", t0, late(0));
  REQUIRE(recent.of("boom", late(0)));
  CHECK(recent.of("boom", late(1))->late_replies == 1);  // counted before the next sample
  recent.record("boom", t0 + 1s, late(1));
  REQUIRE(recent.of("boom", late(1)));
  CHECK(recent.of("boom", late(1))->late_replies == 1);
  for (int s = 2; s <= 11 * 60; ++s) recent.record("boom", t0 + std::chrono::seconds(s), late(1));
  CHECK(recent.of("boom", late(1))->late_replies == 0);
}

TEST_CASE("recent failures: never fewer than since start when those began less than a sample ago") {
  // A console reset then a time-out before the next second's sample: "1 since start" must not
  // read "no errors in 10 min" beside it.
  RecentFailures recent;
  recent.record("boom", t0, FailureCounts{5, 5, 0, 0, 0});
  recent.record("boom", t0 + 1s, FailureCounts{7, 7, 0, 0, 0});
  const FailureCounts after_reset{1, 1, 0, 0, 0};
  REQUIRE(recent.of("boom", after_reset));
  CHECK(recent.of("boom", after_reset)->timeouts == 1);
  CHECK(recent.of("boom", after_reset)->polls_failed == 1);
}

TEST_CASE("recent failures: counters set back to zero count anew, forget and keep_only drop sensors") {
  RecentFailures recent;
  recent.record("boom", t0, FailureCounts{5, 5, 0, 0, 0});
  recent.record("boom", t0 + 1s, FailureCounts{0, 0, 0, 0, 0});  // reset
  recent.record("boom", t0 + 2s, FailureCounts{1, 1, 0, 0, 0});
  CHECK(recent.of("boom", FailureCounts{1, 1, 0, 0, 0})->timeouts == 1);
  recent.record("jib", t0, late(0));
  recent.record("jib", t0 + 1s, late(0));
  recent.forget("boom");
  CHECK_FALSE(recent.of("boom", FailureCounts{1, 1, 0, 0, 0}));
  recent.keep_only({"mast"});
  CHECK_FALSE(recent.of("jib", late(0)));
}

TEST_CASE("recent failures: a bus counts its own sensors' failures, since start and recent") {
  std::vector<SensorStatus> sensors(3);
  sensors[0].bus = "line1";
  sensors[0].timeouts = 4;
  sensors[0].recent_failures = FailureCounts{0, 1, 0, 0, 0};
  sensors[1].bus = "line1";
  sensors[1].late_replies = 2;
  sensors[1].recent_failures = FailureCounts{};
  sensors[2].bus = "line2";
  sensors[2].timeouts = 100;
  BusStatus line1;
  line1.name = "line1";
  add_sensor_failures(line1, sensors);
  CHECK(line1.failures.timeouts == 4);
  CHECK(line1.failures.late_replies == 2);
  REQUIRE(line1.recent_failures);
  CHECK(line1.recent_failures->timeouts == 1);
  BusStatus line2;
  line2.name = "line2";
  add_sensor_failures(line2, sensors);
  CHECK(line2.failures.timeouts == 100);
  CHECK_FALSE(line2.recent_failures);  // its sensor has not been counted yet
}
