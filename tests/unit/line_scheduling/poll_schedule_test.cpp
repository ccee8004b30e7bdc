// The bus's poll timing (line_scheduling/poll_schedule.h) as arithmetic on given time points: the
// period while a sensor answers, a back-off that doubles up to the cap while it does not.
#include <doctest/doctest.h>

#include "line_scheduling/bus_scheduler.h"
#include "line_scheduling/poll_schedule.h"

using namespace tiltgate;
using namespace std::chrono_literals;

TEST_CASE("an unanswered sensor waits its period, then twice as long per failure, up to 5 s") {
  const auto cap = BusScheduler::max_backoff;
  CHECK(cap == 5000ms);
  CHECK(backoff_interval(100ms, 1, cap) == 100ms);
  CHECK(backoff_interval(100ms, 2, cap) == 200ms);
  CHECK(backoff_interval(100ms, 3, cap) == 400ms);
  CHECK(backoff_interval(100ms, 6, cap) == 3200ms);
  CHECK(backoff_interval(100ms, 7, cap) == 5000ms);
  CHECK(backoff_interval(100ms, 1000, cap) == 5000ms);  // no overflow however long it is dead
}

TEST_CASE("a poll period above the back-off cap is kept while the sensor is offline") {
  CHECK(backoff_interval(10s, 1, 5s) == 10s);
  CHECK(backoff_interval(10s, 5, 5s) == 10s);
}

TEST_CASE("failed polls push the next poll out from now, and one answer restores the period") {
  const auto t0 = SteadyClock::time_point{} + 1h;
  PollSchedule schedule{t0};
  auto now = t0;
  std::vector<std::chrono::milliseconds> waits;
  for (int i = 0; i < 9; ++i) {
    schedule = after_poll(schedule, /*answered=*/false, 100ms, 5s, now);
    waits.push_back(std::chrono::duration_cast<std::chrono::milliseconds>(schedule.due - now));
    now = schedule.due + 7ms;  // each poll ends a little after it was due
  }
  CHECK(waits == std::vector<std::chrono::milliseconds>{100ms, 200ms, 400ms, 800ms, 1600ms,
                                                         3200ms, 5000ms, 5000ms, 5000ms});
  CHECK(schedule.failures == 9);

  const auto last_due = schedule.due;
  schedule = after_poll(schedule, /*answered=*/true, 100ms, 5s, last_due + 7ms);
  CHECK(schedule.failures == 0);
  CHECK(schedule.due == last_due + 100ms);  // at its period again, not after 5 s
  schedule = after_poll(schedule, /*answered=*/true, 100ms, 5s, schedule.due + 3ms);
  CHECK(schedule.due == last_due + 200ms);
}

TEST_CASE("an answering sensor keeps its cadence, and polls late only when the bus is behind") {
  const auto t0 = SteadyClock::time_point{} + 1h;
  PollSchedule schedule{t0};
  schedule = after_poll(schedule, true, 100ms, 5s, t0 + 20ms);
  CHECK(schedule.due == t0 + 100ms);
  schedule = after_poll(schedule, true, 100ms, 5s, t0 + 350ms);  // the bus fell behind
  CHECK(schedule.due == t0 + 350ms);
}

TEST_CASE("a poll held up by less than one period more keeps the cadence: the next is made up for") {
  const auto t0 = SteadyClock::time_point{} + 1h;
  PollSchedule schedule{t0};
  // Due at t0, polled only at t0 + 60 ms (it waited behind a probe): the next stays due at
  // t0 + 50 ms, already past, so it goes as soon as the round lets it.
  schedule = after_poll(schedule, true, 50ms, 5s, t0 + 60ms);
  CHECK(schedule.due == t0 + 50ms);
  schedule = after_poll(schedule, true, 50ms, 5s, t0 + 63ms);
  CHECK(schedule.due == t0 + 100ms);  // back in step
  // More than one period behind: from now.
  schedule = after_poll(schedule, true, 50ms, 5s, t0 + 201ms);
  CHECK(schedule.due == t0 + 201ms);
}
