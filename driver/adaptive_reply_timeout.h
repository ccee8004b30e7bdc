// The reply time-out of one sensor, adapted to how late it really answers. A sensor behind a
// slow adapter (USB-RS485 adapters add up to 16 ms each way) or a busy one can answer after the
// bus's time-out; the Line then discards its late reply (driver/line.h), so without adapting
// it would fail every poll, or pass and fail in turn. Pure: fed the Line's timing of each
// transaction.
//
// - Raise: a late reply raises the time-out to cover it with margin (kept within the bus's
//   max_timeout_ms) and marks the sensor as answering late.
// - Decay: after kOnTimeRun on-time replies in a row, the time-out moves halfway down toward
//   what the slowest of them needed (never below the bus's timeout_ms), so one slow spell does
//   not cost the bus forever, and a sensor that is still slow is not pushed back into time-outs.
//   The sensor stops counting as late once such a run was all within the bus's own time-out.
#pragma once

#include <chrono>
#include <cstdint>

#include "driver/line.h"

namespace tiltgate {

// A bus's reply time-out settings, as a driver needs them.
struct ReplyTimeouts {
  std::chrono::milliseconds base{50};  // timeout_ms: what every sensor starts with
  std::chrono::milliseconds max{500};  // max_timeout_ms: the most it adapts up to
};

class AdaptiveReplyTimeout {
 public:
  // On-time replies in a row before the time-out decays one step.
  static constexpr std::uint32_t kOnTimeRun = 50;

  explicit AdaptiveReplyTimeout(ReplyTimeouts limits);

  // One transaction's timing, as the Line reported it.
  void record(const LineTiming& timing);

  std::chrono::milliseconds current() const { return current_; }
  // Has answered after the bus's time-out, and not yet shown a run of replies within it.
  bool answers_late() const { return answers_late_; }
  const ReplyTimeouts& limits() const { return limits_; }

  // The time-out that covers a reply that took `delay`: half as much again plus 10 ms, rounded
  // up to 10 ms, within the limits.
  std::chrono::milliseconds covering(std::chrono::milliseconds delay) const;

 private:
  ReplyTimeouts limits_;
  std::chrono::milliseconds current_;
  bool answers_late_ = false;
  std::uint32_t on_time_run_ = 0;
  std::chrono::milliseconds slowest_in_run_{0};
};

}  // namespace tiltgate
