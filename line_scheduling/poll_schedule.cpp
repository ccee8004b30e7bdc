#include "line_scheduling/poll_schedule.h"

#include <algorithm>

namespace tiltgate {

std::chrono::milliseconds backoff_interval(std::chrono::milliseconds period, int failures,
                                           std::chrono::milliseconds cap) {
  const auto longest = std::max(period, cap);
  auto wait = period;
  // Doubling stops at the cap, so it cannot overflow however long the sensor stays dead.
  for (int i = 1; i < failures && wait < longest; ++i) wait *= 2;
  return std::min(wait, longest);
}

PollSchedule after_poll(PollSchedule schedule, bool answered, std::chrono::milliseconds period,
                        std::chrono::milliseconds cap, SteadyClock::time_point now) {
  if (answered) {
    // One period behind at most: a poll a long turn held up is made up for at once.
    const SteadyClock::time_point next = schedule.due + period;
    return {next + period >= now ? next : now, 0};
  }
  const int failures = std::min(schedule.failures + 1, 1000);
  return {now + backoff_interval(period, failures, cap), failures};
}

}  // namespace tiltgate
