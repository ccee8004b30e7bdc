// A sensor's adaptive reply time-out: raised to cover a late reply, within the bus's maximum,
// and lowered only slowly after a long run of on-time replies.
#include <doctest/doctest.h>

#include "driver/adaptive_reply_timeout.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using std::chrono::milliseconds;

namespace {

LineTiming late(milliseconds delay) {
  LineTiming t;
  t.late_replies = 1;
  t.late_delay = delay;
  return t;
}

LineTiming on_time(milliseconds delay) {
  LineTiming t;
  t.reply_delay = delay;
  return t;
}

void on_time_run(AdaptiveReplyTimeout& timeout, milliseconds delay) {
  for (std::uint32_t i = 0; i < AdaptiveReplyTimeout::kOnTimeRun; ++i) timeout.record(on_time(delay));
}

}  // namespace

TEST_CASE("a sensor starts with the bus's time-out and is not late") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  CHECK(timeout.current() == 50ms);
  CHECK_FALSE(timeout.answers_late());
}

TEST_CASE("a late reply raises the time-out to cover it with margin") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(late(120ms));
  CHECK(timeout.answers_late());
  CHECK(timeout.current() == 190ms);  // 120 + 60 + 10
  timeout.record(late(80ms));         // an earlier, shorter lateness never lowers it
  CHECK(timeout.current() == 190ms);
}

TEST_CASE("the time-out never adapts past the bus's maximum") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(late(900ms));
  CHECK(timeout.current() == 500ms);
  AdaptiveReplyTimeout fixed({50ms, 50ms});
  fixed.record(late(300ms));
  CHECK(fixed.current() == 50ms);
  CHECK(fixed.answers_late());
}

TEST_CASE("a time-out without any reply changes nothing") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(LineTiming{});
  CHECK(timeout.current() == 50ms);
  CHECK_FALSE(timeout.answers_late());
}

TEST_CASE("a still slow sensor keeps its raised time-out and stays marked late") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(late(300ms));
  const auto raised = timeout.current();
  for (int run = 0; run < 5; ++run) on_time_run(timeout, 300ms);
  CHECK(timeout.current() == raised);
  CHECK(timeout.answers_late());
}

TEST_CASE("a sensor that answers in time again decays back to the bus's time-out, slowly") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(late(300ms));
  const auto raised = timeout.current();
  for (std::uint32_t i = 0; i + 1 < AdaptiveReplyTimeout::kOnTimeRun; ++i) {
    timeout.record(on_time(5ms));
  }
  CHECK(timeout.current() == raised);  // not before a whole run
  timeout.record(on_time(5ms));
  CHECK(timeout.current() < raised);
  CHECK(timeout.current() > 50ms);  // halfway, not at once
  CHECK_FALSE(timeout.answers_late());
  for (int run = 0; run < 10; ++run) on_time_run(timeout, 5ms);
  CHECK(timeout.current() == 50ms);
}

TEST_CASE("a late reply in a run of on-time replies starts the run again") {
  AdaptiveReplyTimeout timeout({50ms, 500ms});
  timeout.record(late(300ms));
  const auto raised = timeout.current();
  for (std::uint32_t i = 0; i + 1 < AdaptiveReplyTimeout::kOnTimeRun; ++i) {
    timeout.record(on_time(5ms));
  }
  timeout.record(late(100ms));
  for (std::uint32_t i = 0; i + 1 < AdaptiveReplyTimeout::kOnTimeRun; ++i) {
    timeout.record(on_time(5ms));
  }
  CHECK(timeout.current() == raised);
  CHECK(timeout.answers_late());
}
