#include "doors/request_rate.h"

#include <algorithm>
#include <cmath>

namespace tiltgate {

using std::chrono::nanoseconds;

RateSchedule RateSchedule::of(double per_second) {
  if (!(per_second > 0)) return {};
  const double interval = std::max(1.0, 1e9 / per_second);
  const double burst = std::max<double>(kMinBurst, std::floor(per_second * kBurst.count() / 1e3));
  return {nanoseconds(std::int64_t(interval)), nanoseconds(std::int64_t(interval * (burst - 1)))};
}

RateLimit::Clock::time_point RateLimit::reserve(Clock::time_point at,
                                                const RateSchedule& schedule) {
  const RateSlot slot = reserve_slot(tat_, at.time_since_epoch(), schedule);
  tat_ = slot.next;
  return Clock::time_point(std::chrono::duration_cast<Clock::duration>(slot.start));
}

void SharedRateLimit::set(double per_second) {
  const RateSchedule schedule = RateSchedule::of(per_second);
  per_second_.store(per_second > 0 ? per_second : 0, std::memory_order_relaxed);
  interval_ns_.store(schedule.interval.count(), std::memory_order_relaxed);
  tolerance_ns_.store(schedule.tolerance.count(), std::memory_order_relaxed);
}

SharedRateLimit::Clock::time_point SharedRateLimit::reserve(Clock::time_point at) {
  const RateSchedule schedule{nanoseconds(interval_ns_.load(std::memory_order_relaxed)),
                              nanoseconds(tolerance_ns_.load(std::memory_order_relaxed))};
  if (schedule.interval.count() == 0) return at;
  std::int64_t tat = tat_ns_.load(std::memory_order_relaxed);
  RateSlot slot;
  do {
    slot = reserve_slot(nanoseconds(tat), at.time_since_epoch(), schedule);
  } while (!tat_ns_.compare_exchange_weak(tat, slot.next.count(), std::memory_order_relaxed));
  return Clock::time_point(std::chrono::duration_cast<Clock::duration>(slot.start));
}

}  // namespace tiltgate
