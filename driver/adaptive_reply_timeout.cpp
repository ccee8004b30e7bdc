#include "driver/adaptive_reply_timeout.h"

#include <algorithm>

namespace tiltgate {

using std::chrono::milliseconds;

namespace {

// Margin on top of a measured reply time: the sensor's lateness varies from poll to poll.
constexpr milliseconds kFixedMargin{10};
constexpr milliseconds kStep{10};

}  // namespace

AdaptiveReplyTimeout::AdaptiveReplyTimeout(ReplyTimeouts limits) : limits_(limits) {
  limits_.max = std::max(limits_.max, limits_.base);
  current_ = limits_.base;
}

milliseconds AdaptiveReplyTimeout::covering(milliseconds delay) const {
  const milliseconds wanted = delay + delay / 2 + kFixedMargin;
  const milliseconds rounded = (wanted + kStep - milliseconds{1}) / kStep * kStep;
  return std::clamp(rounded, limits_.base, limits_.max);
}

void AdaptiveReplyTimeout::record(const LineTiming& timing) {
  if (timing.late_replies > 0 && timing.late_delay) {
    answers_late_ = true;
    on_time_run_ = 0;
    slowest_in_run_ = milliseconds{0};
    current_ = std::max(current_, covering(*timing.late_delay));
    return;
  }
  if (!timing.reply_delay) {
    on_time_run_ = 0;  // no answer at all: neither late nor on time
    slowest_in_run_ = milliseconds{0};
    return;
  }
  ++on_time_run_;
  slowest_in_run_ = std::max(slowest_in_run_, *timing.reply_delay);
  if (on_time_run_ < kOnTimeRun) return;
  const milliseconds target = covering(slowest_in_run_);
  if (target < current_) {
    // Halfway, in whole steps: slow, so a sensor whose lateness comes and goes does not flap.
    const milliseconds halfway = target + (current_ - target) / 2;
    current_ = halfway - target < kStep ? target : halfway;
  }
  if (slowest_in_run_ <= limits_.base) answers_late_ = false;
  on_time_run_ = 0;
  slowest_in_run_ = milliseconds{0};
}

}  // namespace tiltgate
