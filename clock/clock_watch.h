// The clock's state as the gateway keeps it (docs/operations.md, "The clock"): read from its
// reader (the kernel, by default) at most once a second, whoever asks, and shared by every
// thread. The buses' threads ask once per reading, to flag one taken while the clock is not
// synchronised; the status API, the metrics, MQTT and Sparkplug ask for what they show. One
// watch per process, owned by the composition root (app/served_gateway.h) and handed to whoever
// needs it.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>

#include "clock/clock_state.h"

namespace tiltgate {

// How often the state changed since the watch began: became unsynchronised (the first read
// included, when it was so), and came back.
struct ClockChanges {
  std::uint64_t losses = 0;
  std::uint64_t recoveries = 0;
};

class ClockWatch {
 public:
  using SteadyNow = std::function<std::chrono::steady_clock::time_point()>;
  // The kernel's state changes slowly (maxerror by 0.5 ms a second); a reading's flag a second
  // late is within what a time service's own update interval already allows.
  static constexpr std::chrono::seconds kRefresh{1};

  // Reads the state once, at once.
  explicit ClockWatch(ClockReader reader = read_kernel_clock,
                      SteadyNow now = &std::chrono::steady_clock::now);
  ClockWatch(const ClockWatch&) = delete;
  ClockWatch& operator=(const ClockWatch&) = delete;

  // The state as last read, read again first when kRefresh has passed since. Any thread; it
  // never waits for another thread's read: while one thread reads, the others take the
  // state before it. Logs (spdlog) once when the clock becomes unsynchronised and once when
  // it comes back.
  ClockState current() const;
  ClockChanges changes() const;

 private:
  // The state read less than kRefresh before `now`, if there is one.
  std::optional<ClockState> fresh(std::chrono::steady_clock::time_point now) const;
  // After a read: the new state kept, the change counted; what to log, done outside the lock.
  enum class Change { none, first_synchronised, lost, recovered };
  Change take(const ClockState& read, std::chrono::steady_clock::time_point at) const;
  static void log(Change change, const ClockState& state);

  ClockReader reader_;
  SteadyNow now_;
  mutable std::mutex mutex_;
  mutable ClockState state_;
  mutable std::optional<std::chrono::steady_clock::time_point> read_at_;  // none before the first
  mutable ClockChanges changes_;
  mutable std::atomic<bool> reading_ = false;  // a thread is in reader_() now
};

}  // namespace tiltgate
