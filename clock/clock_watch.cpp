#include "clock/clock_watch.h"

#include <spdlog/spdlog.h>

#include <utility>

namespace tiltgate {

ClockWatch::ClockWatch(ClockReader reader, SteadyNow now)
    : reader_(std::move(reader)), now_(std::move(now)) {
  // Read at once: no caller ever sees a state nobody read, and the log says at start-up
  // whether the clock can be trusted.
  (void)current();
}

std::optional<ClockState> ClockWatch::fresh(std::chrono::steady_clock::time_point now) const {
  std::lock_guard lock(mutex_);
  if (read_at_ && now - *read_at_ < kRefresh) return state_;
  return std::nullopt;
}

ClockState ClockWatch::current() const {
  const auto now = now_();
  if (const auto known = fresh(now)) return *known;
  // One thread reads; the others go on with the state before (a bus thread never waits for
  // the syscall, nor for the log line a change makes).
  if (reading_.exchange(true)) {
    std::lock_guard lock(mutex_);
    return state_;
  }
  // Another thread may have read between the look above and the exchange.
  if (const auto known = fresh(now)) {
    reading_.store(false);
    return *known;
  }
  const ClockState read = reader_();
  const Change change = take(read, now);
  reading_.store(false);
  log(change, read);
  return read;
}

ClockWatch::Change ClockWatch::take(const ClockState& read,
                                    std::chrono::steady_clock::time_point at) const {
  std::lock_guard lock(mutex_);
  const bool first = !read_at_.has_value();
  const bool was_synchronised = state_.synchronised;
  state_ = read;
  read_at_ = at;
  if (!read.synchronised) {
    if (!first && !was_synchronised) return Change::none;
    ++changes_.losses;
    return Change::lost;
  }
  if (first) return Change::first_synchronised;
  if (was_synchronised) return Change::none;
  ++changes_.recoveries;
  return Change::recovered;
}

void ClockWatch::log(Change change, const ClockState& state) {
  const double error_ms = state.error_ms.value_or(0.0);
  switch (change) {
    case Change::none: return;
    case Change::first_synchronised:
      spdlog::info("clock: the system clock is synchronised, maximum error {:.1f} ms", error_ms);
      return;
    case Change::lost:
      spdlog::warn("clock: the system clock is not synchronised ({}); readings taken meanwhile "
                   "are flagged",
                   clock_problem_text(state.problem));
      return;
    case Change::recovered:
      spdlog::info("clock: the system clock is synchronised again, maximum error {:.1f} ms",
                   error_ms);
      return;
  }
}

ClockChanges ClockWatch::changes() const {
  std::lock_guard lock(mutex_);
  return changes_;
}

}  // namespace tiltgate
