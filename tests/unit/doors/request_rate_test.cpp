// The request rates' arithmetic (doors/request_rate.h): slots one interval apart, a burst
// taken early, arrival order kept, and no limit at 0.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "doors/request_rate.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST_CASE("a rate's schedule: the interval, and a burst of 10 ms of it, at least 4 requests") {
  const RateSchedule fast = RateSchedule::of(20000);
  CHECK(fast.interval == 50us);
  CHECK(fast.tolerance == 199 * 50us);  // 200 requests in a burst
  const RateSchedule slow = RateSchedule::of(10);
  CHECK(slow.interval == 100ms);
  CHECK(slow.tolerance == 3 * 100ms);  // 4 requests
  CHECK(RateSchedule::of(0).interval == 0ns);
  CHECK(RateSchedule::of(-5).interval == 0ns);
}

TEST_CASE("reserve_slot: a burst at once, then one slot an interval") {
  const RateSchedule schedule{10ms, 20ms};  // 3 at once
  std::chrono::nanoseconds tat{0};
  const std::chrono::nanoseconds at = 1s;
  std::vector<std::chrono::nanoseconds> starts;
  for (int i = 0; i < 5; ++i) {
    const RateSlot slot = reserve_slot(tat, at, schedule);
    starts.push_back(slot.start);
    tat = slot.next;
  }
  CHECK(starts == std::vector<std::chrono::nanoseconds>{1s, 1s, 1s, 1s + 10ms, 1s + 20ms});
  // Idle long enough, and the burst is back.
  CHECK(reserve_slot(tat, 2s, schedule).start == 2s);
  // No limit: at once, the schedule untouched.
  const RateSlot free = reserve_slot(tat, 3s, RateSchedule{});
  CHECK(free.start == 3s);
  CHECK(free.next == tat);
}

TEST_CASE("RateLimit keeps one client's schedule") {
  RateLimit limit;
  const RateSchedule schedule = RateSchedule::of(100);  // 10 ms apart, 4 at once
  const Clock::time_point now = Clock::now();
  for (int i = 0; i < 4; ++i) CHECK(limit.reserve(now, schedule) == now);
  CHECK(limit.reserve(now, schedule) == now + 10ms);
  CHECK(limit.reserve(now, schedule) == now + 20ms);
}

TEST_CASE("SharedRateLimit: every thread's reservations share one schedule, none lost") {
  SharedRateLimit limit(1000);  // 1 ms apart, 10 at once
  const Clock::time_point now = Clock::now();
  std::vector<Clock::time_point> first(200), second(200);
  std::thread a([&] {
    for (auto& start : first) start = limit.reserve(now);
  });
  std::thread b([&] {
    for (auto& start : second) start = limit.reserve(now);
  });
  a.join();
  b.join();
  std::vector<Clock::time_point> all(first);
  all.insert(all.end(), second.begin(), second.end());
  std::sort(all.begin(), all.end());
  // 400 reservations: 10 at once, then one a millisecond, each slot taken once.
  CHECK(all[9] == now);
  for (std::size_t i = 10; i < all.size(); ++i) CHECK(all[i] - all[i - 1] == 1ms);
  limit.set(0);
  CHECK(limit.reserve(now) == now);
  CHECK(limit.per_second() == 0);
}
