// BusScheduler on an io_context with a fake line and fake drivers (the bench of
// unit/support/scheduler_bench.h): back-off from a dead sensor, writes ahead of due polls but
// never into a running poll, the write deadline, and the address check. Assertions are on
// counts and order; where time matters the bounds are wide.
#include <doctest/doctest.h>

#include <optional>

#include "gateway/bus_scheduler.h"
#include "unit/support/scheduler_bench.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("a dead sensor is polled far less often than a live one on the same bus") {
  SchedulerBench bus;
  auto& live = fake_driver(bus.add("live", 1, 10ms));
  auto& dead = fake_driver(bus.add("dead", 2, 10ms));
  dead.answers = false;
  bus.start();
  bus.io.run_for(1500ms);
  // Without back-off both get ~150 polls. With it the dead one is polled after 10, 20, 40,
  // ... 640 ms: 8 polls in 1.5 s (fewer if the machine is slow, never more).
  CAPTURE(live.polls);
  CAPTURE(dead.polls);
  CHECK(dead.polls >= 3);
  CHECK(dead.polls <= 12);
  CHECK(live.polls > 3 * dead.polls);
}

TEST_CASE("a write queued during a poll waits for it, then runs before the polls that are due") {
  SchedulerBench bus;
  auto& first = bus.add("a", 1);
  auto& second = bus.add("b", 2);
  auto& a = fake_driver(first);
  a.poll_time = 50ms;  // both sensors are due at once; a goes first and holds the line
  std::optional<WriteResult> result;
  a.on_poll = [&] {
    if (a.polls == 1) bus.write(second, WriteTarget::filter, 3, SteadyClock::now() + 10s, result);
  };
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result && fake_driver(second).polls >= 1; }));
  CHECK(result->has_value());
  const BusEvents expected = {"a poll", "a poll end", "b write", "b write end", "b poll"};
  CHECK(BusEvents(bus.events.begin(), bus.events.begin() + 5) == expected);
  CHECK(bus.scheduler.stats().writes == 1);
}

TEST_CASE("a write still queued at its deadline is answered busy and never runs") {
  SchedulerBench bus;
  auto& first = bus.add("a", 1);
  auto& second = bus.add("b", 2);
  auto& a = fake_driver(first);
  a.poll_time = 1000ms;  // holds the line far past the write's deadline
  std::optional<WriteResult> result;
  a.on_poll = [&] {
    if (a.polls == 1) bus.write(second, WriteTarget::filter, 3, SteadyClock::now() + 20ms, result);
  };
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls >= 2 || fake_driver(second).polls >= 1; }));
  REQUIRE(result.has_value());
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error().kind == WriteErrorKind::busy);
  CHECK(fake_driver(second).writes.empty());
  CHECK(bus.scheduler.stats().writes_expired == 1);
  CHECK(bus.scheduler.stats().writes == 0);
}

TEST_CASE("a write already on the wire at its deadline is waited for and succeeds") {
  SchedulerBench bus;
  auto& sensor = bus.add("a", 1, 10s);
  auto& a = fake_driver(sensor);
  a.write_time = 500ms;
  std::optional<WriteResult> result;
  // Queued before the loop starts, so it is the first thing on the wire.
  bus.write(sensor, WriteTarget::filter, 3, SteadyClock::now() + 100ms, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(result->has_value());
  CHECK(a.writes.size() == 1);
  CHECK(bus.scheduler.stats().writes_expired == 0);
}

TEST_CASE("the bus refuses to give a sensor the address another sensor on it has now") {
  SchedulerBench bus;
  auto& left = bus.add("left", 223);
  auto& right = bus.add("right", 101);
  auto taken = bus.scheduler.check_address_free(right, WriteTarget::bus_address, 223);
  REQUIRE_FALSE(taken.has_value());
  CHECK(taken.error().kind == WriteErrorKind::bad_value);
  CHECK(taken.error().detail.find("left") != std::string::npos);
  CHECK(bus.scheduler.check_address_free(right, WriteTarget::bus_address, 224).has_value());
  CHECK(bus.scheduler.check_address_free(right, WriteTarget::bus_address, 101).has_value());
  CHECK(bus.scheduler.check_address_free(right, WriteTarget::filter, 223).has_value());

  // After left moved (the driver follows it), 223 is free and 300 is taken.
  std::optional<WriteResult> moved;
  bus.write(left, WriteTarget::bus_address, 300, SteadyClock::now() + 10s, moved);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return moved.has_value(); }));
  REQUIRE(moved->has_value());
  CHECK(bus.scheduler.check_address_free(right, WriteTarget::bus_address, 223).has_value());
  CHECK_FALSE(bus.scheduler.check_address_free(right, WriteTarget::bus_address, 300).has_value());
}

TEST_CASE("a queued address write is checked again when it starts, and refused if taken by then") {
  SchedulerBench bus;
  auto& left = bus.add("left", 223);
  auto& right = bus.add("right", 101);
  std::optional<WriteResult> first, second;
  // Both pass the check when queued (300 is free); the first moves right to 300.
  bus.write(right, WriteTarget::bus_address, 300, SteadyClock::now() + 10s, first);
  bus.write(left, WriteTarget::bus_address, 300, SteadyClock::now() + 10s, second);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return first.has_value() && second.has_value(); }));
  CHECK(first->has_value());
  REQUIRE_FALSE(second->has_value());
  CHECK(second->error().kind == WriteErrorKind::bad_value);
  CHECK(fake_driver(left).writes.empty());
  CHECK(left.driver->state().bus_address == 223);
  CHECK(right.driver->state().bus_address == 300);
}
