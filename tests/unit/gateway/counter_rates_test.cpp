// Rates over a sliding window of counter samples: polls/s and bus use on the status page.
#include <doctest/doctest.h>

#include "gateway/counter_rates.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {
const CounterRates::Clock::time_point t0{};
}

TEST_CASE("counter rates: none until two samples, then growth per second") {
  CounterRates rates(5s);
  CHECK_FALSE(rates.rate(0));
  rates.record(t0, {100, 0.0});
  CHECK_FALSE(rates.rate(0));
  rates.record(t0 + 2s, {120, 0.5});
  REQUIRE(rates.rate(0));
  CHECK(*rates.rate(0) == doctest::Approx(10.0));
  CHECK(*rates.rate(1) == doctest::Approx(0.25));
  CHECK_FALSE(rates.rate(2));  // no such counter
}

TEST_CASE("counter rates: the rate covers the last window, not the whole history") {
  CounterRates rates(5s);
  // 1 per second for 10 s, then 11 per second for 6 s.
  for (int s = 0; s <= 10; ++s) rates.record(t0 + std::chrono::seconds(s), {double(s)});
  for (int s = 11; s <= 16; ++s)
    rates.record(t0 + std::chrono::seconds(s), {10.0 + 11.0 * (s - 10)});
  REQUIRE(rates.rate(0));
  CHECK(*rates.rate(0) == doctest::Approx(11.0));
}

TEST_CASE("counter rates: a counter that went down gives none, not a negative rate") {
  CounterRates rates(5s);
  rates.record(t0, {50});
  rates.record(t0 + 1s, {3});
  CHECK_FALSE(rates.rate(0));
}

TEST_CASE("counter rates: growth over a long window sampled every second keeps few samples") {
  // Errors in the last 10 minutes, sampled each second, kept 10 s apart.
  CounterRates errors(600s, 10s);
  errors.record(t0, {0});
  CHECK_FALSE(errors.growth(0));  // one sample: nothing to compare with
  // One error at 5 s, then none for 20 minutes.
  for (int s = 1; s <= 1200; ++s) errors.record(t0 + std::chrono::seconds(s), {s >= 5 ? 1.0 : 0.0});
  REQUIRE(errors.growth(0));
  CHECK(*errors.growth(0) == 0.0);  // the error is older than the window
  CHECK(errors.samples() <= 62);      // 10 min at 10 s, the one spanning it and the newest
  // A new one now counts at once: the newest sample is always the latest totals.
  errors.record(t0 + 1201s, {2});
  CHECK(*errors.growth(0) == 1.0);
}

TEST_CASE("counter rates: growth to a live total from the oldest sample, none below it") {
  CounterRates errors(600s, 10s);
  CHECK_FALSE(errors.growth_to(0, 4));  // no sample yet
  errors.record(t0, {2});
  CHECK(*errors.growth_to(0, 4) == 2.0);  // one sample is enough: the total is now's
  CHECK_FALSE(errors.growth_to(0, 1));    // restarted since
  CHECK_FALSE(errors.growth_to(1, 4));    // no such counter
}

TEST_CASE("counter rates: growth since the first sample until the window is full, then over it") {
  CounterRates errors(600s, 10s);
  errors.record(t0, {0});
  errors.record(t0 + 1s, {3});
  CHECK(*errors.growth(0) == 3.0);
  for (int s = 2; s <= 300; ++s) errors.record(t0 + std::chrono::seconds(s), {3.0 + s / 100});
  CHECK(*errors.growth(0) == 6.0);  // 3 at 1 s, 3 more by 300 s: all within the window
}

TEST_CASE("counter rates: clear forgets the samples, so counters set back to zero count anew") {
  CounterRates errors(600s, 10s);
  errors.record(t0, {0});
  errors.record(t0 + 20s, {7});
  errors.clear();
  errors.record(t0 + 21s, {0});
  errors.record(t0 + 22s, {1});
  CHECK(*errors.growth(0) == 1.0);
}

TEST_CASE("counter rates: recorded restarting, counters that went back to zero count anew") {
  CounterRates errors(600s, 10s);
  errors.record_restarting(t0, {5, 1});
  errors.record_restarting(t0 + 20s, {9, 1});
  CHECK(*errors.growth(0) == 4.0);
  errors.record_restarting(t0 + 21s, {0, 0});  // reset
  errors.record_restarting(t0 + 22s, {2, 0});
  CHECK(*errors.growth(0) == 2.0);
  CHECK(*errors.growth(1) == 0.0);
}
