// The log throttle: a client that floods the gateway with bad requests gets a few log lines and
// one summary per interval, not one line per request.
#include <doctest/doctest.h>

#include "doors/log_throttle.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Clock = LogThrottle::Clock;

namespace {

const Clock::time_point t0{};

int admitted(LogThrottle& throttle, const std::string& address, int problems,
             Clock::time_point at) {
  int logged = 0;
  for (int i = 0; i < problems; ++i) logged += throttle.admit(address, at) ? 1 : 0;
  return logged;
}

}  // namespace

TEST_CASE("log throttle: the first five problems of an address are logged, the rest counted") {
  LogThrottle throttle;
  CHECK(admitted(throttle, "10.0.0.5", 1500, t0) == 5);
  CHECK(throttle.take_summaries(t0 + 59s).empty());
  const auto summaries = throttle.take_summaries(t0 + 60s);
  REQUIRE(summaries.size() == 1);
  CHECK(summaries[0].address == "10.0.0.5");
  CHECK(summaries[0].count == 1495);
  CHECK(summaries[0].span == 60s);
}

TEST_CASE("log throttle: each address has its own burst") {
  LogThrottle throttle;
  CHECK(admitted(throttle, "10.0.0.5", 6, t0) == 5);
  CHECK(throttle.admit("10.0.0.6", t0));
  const auto summaries = throttle.take_summaries(t0 + 60s);
  REQUIRE(summaries.size() == 1);
  CHECK(summaries[0].address == "10.0.0.5");
  CHECK(summaries[0].count == 1);
}

TEST_CASE("log throttle: a flood that goes on gets one summary per interval and no new burst") {
  LogThrottle throttle;
  CHECK(admitted(throttle, "10.0.0.5", 10, t0) == 5);
  CHECK(admitted(throttle, "10.0.0.5", 10, t0 + 61s) == 0);  // the first interval ends here
  CHECK(admitted(throttle, "10.0.0.5", 7, t0 + 100s) == 0);
  auto first = throttle.take_summaries(t0 + 100s);
  REQUIRE(first.size() == 1);
  CHECK(first[0].count == 5);
  CHECK(first[0].span == 61s);
  auto second = throttle.take_summaries(t0 + 121s);
  REQUIRE(second.size() == 1);
  CHECK(second[0].count == 17);
}

TEST_CASE("log throttle: an address quiet for a whole interval starts afresh") {
  LogThrottle throttle;
  CHECK(admitted(throttle, "10.0.0.5", 6, t0) == 5);
  CHECK(throttle.take_summaries(t0 + 60s).size() == 1);
  CHECK(throttle.take_summaries(t0 + 120s).empty());  // nothing in the second interval
  CHECK(throttle.tracked_addresses() == 0);
  CHECK(admitted(throttle, "10.0.0.5", 6, t0 + 130s) == 5);
}

TEST_CASE("log throttle: a few problems, then quiet, are forgotten without a summary") {
  LogThrottle throttle;
  CHECK(admitted(throttle, "10.0.0.5", 3, t0) == 3);
  CHECK_FALSE(throttle.next_summary_due().has_value());
  CHECK(throttle.take_summaries(t0 + 60s).empty());
  CHECK(throttle.tracked_addresses() == 0);
}

TEST_CASE("log throttle: memory is bounded, and an evicted address's count is still summarized") {
  LogThrottleOptions options;
  options.max_addresses = 3;
  LogThrottle throttle(options);
  CHECK(admitted(throttle, "10.0.0.1", 8, t0) == 5);
  throttle.admit("10.0.0.2", t0 + 1s);
  throttle.admit("10.0.0.3", t0 + 2s);
  for (int i = 4; i < 200; ++i) throttle.admit("10.0.0." + std::to_string(i), t0 + 3s);
  CHECK(throttle.tracked_addresses() == 3);
  const auto summaries = throttle.take_summaries(t0 + 3s);
  REQUIRE(summaries.size() == 1);
  CHECK(summaries[0].address == "10.0.0.1");
  CHECK(summaries[0].count == 3);
}

TEST_CASE("log throttle: the next summary is due when the earliest counting interval ends") {
  LogThrottleOptions options;
  options.burst = 1;
  options.interval = 10s;
  LogThrottle throttle(options);
  throttle.admit("a", t0);
  CHECK_FALSE(throttle.next_summary_due().has_value());  // logged, nothing counted
  throttle.admit("b", t0 + 2s);
  throttle.admit("b", t0 + 3s);
  throttle.admit("a", t0 + 4s);
  REQUIRE(throttle.next_summary_due().has_value());
  CHECK(*throttle.next_summary_due() == t0 + 10s);
}

TEST_CASE("log throttle: it tells an address with problems in its interval from one without") {
  LogThrottle throttle;
  CHECK_FALSE(throttle.tracks("10.0.0.5"));
  throttle.admit("10.0.0.5", t0);
  CHECK(throttle.tracks("10.0.0.5"));
  CHECK_FALSE(throttle.tracks("10.0.0.6"));
  CHECK(throttle.take_summaries(t0 + 60s).empty());
  CHECK_FALSE(throttle.tracks("10.0.0.5"));  // quiet for its interval: forgotten
}
