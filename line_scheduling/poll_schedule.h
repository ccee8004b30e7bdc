// When a bus polls one sensor next: at its poll period while it answers, and with a back-off
// while it does not, so a dead sensor costs the bus one time-out every few seconds instead of
// one per poll period. Pure arithmetic on time points the caller passes in.
#pragma once

#include <chrono>

#include "driver/sensor_state.h"

namespace tiltgate {

struct PollSchedule {
  SteadyClock::time_point due;
  int failures = 0;  // consecutive polls without a reply
};

// The wait after the `failures`-th unanswered poll in a row: the period after the first, then
// doubled per failure, up to `cap`. Never shorter than the period: a sensor with a period
// above the cap is not polled more often offline than online.
std::chrono::milliseconds backoff_interval(std::chrono::milliseconds period, int failures,
                                           std::chrono::milliseconds cap);

// The schedule after a poll that ended at `now`. Answered: back to the period, keeping the
// cadence (due + period) while the bus keeps up: also when that is already past, by up to one
// period, so a poll that waited behind a long turn (a scan's probe, a failing sensor's
// time-out) costs no poll; the next then goes as soon as the round lets it. Further behind,
// now (the bus then shares itself earliest-due-first instead of letting one sensor catch up
// in a burst). Unanswered: now + backoff_interval().
PollSchedule after_poll(PollSchedule schedule, bool answered, std::chrono::milliseconds period,
                        std::chrono::milliseconds cap, SteadyClock::time_point now);

}  // namespace tiltgate
