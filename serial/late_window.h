// How long an attempt that timed out holds a line: its reply wait, then the late-reply window
// (serial/serial_line.h, "Late replies"). Pure arithmetic, shared by SerialLine and the line's
// time budget (line_scheduling/line_budget.h), so the two never disagree.
#pragma once

#include <algorithm>
#include <chrono>

namespace tiltgate {

// A late burst has ended once the line has been quiet this long after its last byte (or the
// guard, if shorter): more than the pause any protocol here allows inside a frame even at
// 1200 baud (1.5 characters, 14 ms), and than a USB adapter's 16 ms latency timer between the
// pieces of one reply. The same time is the look for a reply that starts just after its deadline.
inline constexpr std::chrono::milliseconds kLateBurstQuiet{20};

// A bus's late-reply settings.
struct LateWindow {
  std::chrono::milliseconds timeout{50};     // timeout_ms: the bus's own reply wait
  std::chrono::milliseconds late_guard{450};  // late_guard_ms

  // The quiet after a late burst's last byte, and the look after a silent deadline.
  constexpr std::chrono::milliseconds burst_quiet() const {
    return std::min(late_guard, kLateBurstQuiet);
  }
  // From the end of a request whose attempt (reply wait `wait`) timed out, the longest the
  // line stays held: until the window closes (timeout + late_guard after the request, which is
  // max_timeout_ms with the defaults; the deadline, for a wait adapted past that) and a late
  // burst ends that started just then.
  constexpr std::chrono::milliseconds held_after(std::chrono::milliseconds wait) const {
    return std::max(timeout + late_guard, wait) + burst_quiet();
  }
  // The same after a short look: a silent attempt given up early, or a garbled reply.
  constexpr std::chrono::milliseconds looked_after(std::chrono::milliseconds wait) const {
    return wait + burst_quiet();
  }
};

}  // namespace tiltgate
