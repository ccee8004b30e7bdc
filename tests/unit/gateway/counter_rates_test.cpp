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
