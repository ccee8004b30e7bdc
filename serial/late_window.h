// How long an attempt that timed out holds a line: its reply wait, then the late-reply window
// (serial/serial_line.h, "Late replies"). Pure arithmetic, shared by SerialLine and the line's
// time budget (gateway/line_budget.h), so the two never disagree.
#pragma once

#include <algorithm>
#include <chrono>

namespace tiltgate {

// A late burst has ended once the line has been quiet this long after its last byte (or the
// guard, if shorter): a few character times even at 1200 baud, and a USB adapter's 16 ms
// latency timer between the pieces of one reply, with room to spare.
inline constexpr std::chrono::milliseconds kLateBurstQuiet{50};

// A bus's late-reply settings.
struct LateWindow {
  std::chrono::milliseconds timeout{50};     // timeout_ms: the bus's own reply wait
  std::chrono::milliseconds late_guard{450};  // late_guard_ms

  // The quiet kept after a time-out at the least: one bus reply wait (or the guard, if shorter).
  constexpr std::chrono::milliseconds short_quiet() const { return std::min(timeout, late_guard); }
  // The quiet after a late burst's last byte.
  constexpr std::chrono::milliseconds burst_quiet() const {
    return std::min(late_guard, kLateBurstQuiet);
  }
  // From the end of a request whose attempt (reply wait `wait`) timed out, the longest the
  // line stays held: the whole window (timeout + late_guard after the request, at least a short
  // quiet past the attempt's own deadline), and a late burst that ends just then.
  constexpr std::chrono::milliseconds held_after(std::chrono::milliseconds wait) const {
    return std::max(timeout + late_guard, wait + short_quiet()) + burst_quiet();
  }
  // The same after a short look: a silent attempt given up early, or a garbled reply.
  constexpr std::chrono::milliseconds looked_after(std::chrono::milliseconds wait) const {
    return wait + short_quiet();
  }
};

}  // namespace tiltgate
