// Requests admitted at a rate (docs/operations.md, "Load on the doors"): a flood of requests
// must never take the cores the serial lines need (the kernel's tty worker that hands a reply's
// bytes to the gateway starved for up to 2 s under a Modbus flood on a 2-core box:
// docs/performance.md, "A flood and the line"). A request beyond the rate is not refused: its
// connection waits until its turn and reads nothing meanwhile, so the client sees a slower
// answer and its socket's flow control (TCP backpressure), never an exception.
//
// The arithmetic is the generic cell rate algorithm as a schedule: each request reserves the
// next free slot (one every 1/rate seconds) and may start up to a burst's worth of slots
// early, so requests are served in arrival order across every client and thread, in bursts
// short enough to leave the cores idle in between. A limit of 0 admits everything at once.
//
// A request that must wait is taken up a little after its slot, on a grid (take_up()): one
// wake-up of a thread then serves every client whose slot has come, and a client held to a
// rate gets its next requests at once, in a burst, rather than each after a wait of its own.
// Waking for every slot cost more CPU than answering the request (at 20000 a second, one wake
// every 50 us).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

namespace tiltgate {

// A limit's slot spacing and how early a request may take its slot.
struct RateSchedule {
  std::chrono::nanoseconds interval{0};   // between two slots; 0: no limit
  std::chrono::nanoseconds tolerance{0};  // a burst of tolerance / interval + 1 at once

  // `per_second` requests a second (0 or less: no limit), in bursts of up to kBurst of the
  // rate's time (at least kMinBurst requests).
  static RateSchedule of(double per_second);

  static constexpr std::chrono::milliseconds kBurst{10};
  static constexpr int kMinBurst = 4;
};

// One reservation: when the request may start, and the limit's next theoretical arrival time.
struct RateSlot {
  std::chrono::nanoseconds start;
  std::chrono::nanoseconds next;
};

// Pure: a request arriving `at` against a limit whose theoretical arrival time is `tat` (both
// on one clock, since its epoch).
inline RateSlot reserve_slot(std::chrono::nanoseconds tat, std::chrono::nanoseconds at,
                             const RateSchedule& schedule) {
  if (schedule.interval.count() == 0) return {at, tat};
  const std::chrono::nanoseconds start = tat - schedule.tolerance > at ? tat - schedule.tolerance : at;
  return {start, (tat > at ? tat : at) + schedule.interval};
}

// When a request whose slot starts at `start` (later than now) is taken up: kHold after it,
// rounded up to the next kGrid.
inline constexpr std::chrono::microseconds kHold{1000};
inline constexpr std::chrono::microseconds kGrid{1000};
inline std::chrono::steady_clock::time_point take_up(std::chrono::steady_clock::time_point start) {
  const auto held = (start + kHold).time_since_epoch();
  const auto grid = std::chrono::duration_cast<std::chrono::steady_clock::duration>(kGrid);
  return std::chrono::steady_clock::time_point((held + grid - std::chrono::nanoseconds(1)) / grid * grid);
}

// One client's limit, used on its connection's thread only.
class RateLimit {
 public:
  using Clock = std::chrono::steady_clock;

  // When a request arriving `at` may be served under `schedule` (`at` when at once).
  Clock::time_point reserve(Clock::time_point at, const RateSchedule& schedule);

 private:
  std::chrono::nanoseconds tat_{0};
};

// The limit of every client together, from any thread: one atomic, no lock.
class SharedRateLimit {
 public:
  using Clock = std::chrono::steady_clock;

  explicit SharedRateLimit(double per_second = 0) { set(per_second); }

  // A reload's new rate, for the reservations from now on.
  void set(double per_second);
  double per_second() const { return per_second_.load(std::memory_order_relaxed); }
  // When a request arriving `at` may be served (`at` when at once); its slot is taken.
  Clock::time_point reserve(Clock::time_point at);

 private:
  std::atomic<double> per_second_{0};
  std::atomic<std::int64_t> interval_ns_{0};
  std::atomic<std::int64_t> tolerance_ns_{0};
  std::atomic<std::int64_t> tat_ns_{0};
};

// When a request arriving `now` may be served: its client's own turn first, then a place among
// everyone's from then (a client held to its own rate keeps no slot of the total idle
// meanwhile); a turn later than now is taken up on the grid (take_up()).
inline std::chrono::steady_clock::time_point next_turn(std::chrono::steady_clock::time_point now,
                                                       RateLimit& own, const RateSchedule& own_schedule,
                                                       SharedRateLimit& total) {
  const std::chrono::steady_clock::time_point turn = total.reserve(own.reserve(now, own_schedule));
  return turn > now ? take_up(turn) : turn;
}

// The same for a request that must also find a place within a share of the total first (the
// console's requests without a session: half of [http] max_requests_per_s), so that the rest
// of the total stays free for the others.
inline std::chrono::steady_clock::time_point next_turn(std::chrono::steady_clock::time_point now,
                                                       RateLimit& own, const RateSchedule& own_schedule,
                                                       SharedRateLimit& share, SharedRateLimit& total) {
  const std::chrono::steady_clock::time_point turn =
      total.reserve(share.reserve(own.reserve(now, own_schedule)));
  return turn > now ? take_up(turn) : turn;
}

}  // namespace tiltgate
