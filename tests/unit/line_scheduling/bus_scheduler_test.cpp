// BusScheduler on an io_context with a fake line and fake drivers (the bench of
// unit/support/scheduler_bench.h): back-off from a dead sensor, a failing sensor's retries
// spread between the others' polls, writes ahead of due polls but never into a running poll,
// a write to a sensor known offline answered at once, the write deadline, a tty gone, and the
// address check. Assertions are on counts and order; where time matters the bounds are wide.
#include <doctest/doctest.h>

#include <algorithm>
#include <optional>

#include "line_scheduling/bus_scheduler.h"
#include "sim/support/captured_log.h"
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

TEST_CASE("a write whose transaction can end before its deadline is sent and succeeds") {
  SchedulerBench bus;
  auto& sensor = bus.add("a", 1, 10s);
  auto& a = fake_driver(sensor);
  a.write_time = 50ms;
  std::optional<WriteResult> result;
  // Queued before the loop starts, so it is the first thing on the wire.
  bus.write(sensor, WriteTarget::filter, 3, SteadyClock::now() + 100ms, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(result->has_value());
  CHECK(a.writes.size() == 1);
  CHECK(bus.scheduler.stats().writes_expired == 0);
}

TEST_CASE("a write whose transaction could not end before its deadline is not sent and answered then") {
  SchedulerBench bus;
  auto& sensor = bus.add("a", 1, 10s);
  auto& a = fake_driver(sensor);
  a.write_time = 500ms;  // the line would hold it that long
  std::optional<WriteResult> result;
  const auto queued = SteadyClock::now();
  bus.write(sensor, WriteTarget::filter, 3, queued + 100ms, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(SteadyClock::now() - queued < 100ms);
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error().kind == WriteErrorKind::no_response);
  CHECK(bus.line.stats().attempts == 0);  // the write went first, and nothing reached the line
}

TEST_CASE("a write whose sensor stops answering mid-way is answered by its deadline, its later steps unsent") {
  SchedulerBench bus;
  bus.line.retries_left_to_the_line = 2;
  auto& sensor = bus.add("a", 1, 10s);
  // Polled between the write's attempts, and often holding the line when a step of the write
  // that ran out of time asks for it again.
  fake_driver(bus.add("b", 2, 20ms)).poll_time = 30ms;
  auto& a = fake_driver(sensor);
  a.write_time = 40ms;
  a.write_exchanges = 3;
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.state().online; }));  // its first poll answered
  bus.line.silent = [&](const LineRequest& request) { return request.bytes.at(0) == 1; };
  std::optional<WriteResult> result;
  const auto queued = SteadyClock::now();
  bus.write(sensor, WriteTarget::filter, 3, queued + 100ms, result);
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(SteadyClock::now() - queued <= 110ms);
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error().kind == WriteErrorKind::no_response);
  // b keeps being polled after, one transaction on the line at a time.
  const int b_polls = fake_driver(*bus.sensors[1]).polls;
  bus.io.run_for(150ms);
  CHECK(fake_driver(*bus.sensors[1]).polls > b_polls);
  CHECK(bus.line.most_at_once == 1);
}

TEST_CASE("a failing sensor's retries each wait for the other sensors' polls") {
  SchedulerBench bus;
  bus.line.retries_left_to_the_line = 2;
  bus.add("a", 1, 10ms);  // due again by the end of each of the dead sensor's attempts
  bus.add("b", 2, 10ms);
  auto& dead = fake_driver(bus.add("dead", 3, 10s));
  dead.poll_time = 50ms;  // each attempt holds the line that long before it times out
  bus.line.silent = [](const LineRequest& request) { return request.bytes.at(0) == 3; };
  bus.line.on_attempt = [&](const LineRequest& request) {
    bus.events.push_back("attempt " + std::to_string(request.bytes.at(0)));
  };
  bus.start();
  REQUIRE(run_until(bus.io, [&] {
    return std::count(bus.events.begin(), bus.events.end(), "dead poll end") == 1;
  }));
  // Between two attempts of the dead sensor, a and b were polled.
  std::vector<std::size_t> attempts;
  for (std::size_t i = 0; i < bus.events.size(); ++i)
    if (bus.events[i] == "attempt 3") attempts.push_back(i);
  REQUIRE(attempts.size() == 3);
  for (std::size_t i = 1; i < attempts.size(); ++i) {
    const BusEvents between(bus.events.begin() + std::ptrdiff_t(attempts[i - 1]),
                            bus.events.begin() + std::ptrdiff_t(attempts[i]));
    CHECK(std::count(between.begin(), between.end(), "a poll end") >= 1);
    CHECK(std::count(between.begin(), between.end(), "b poll end") >= 1);
  }
  CHECK(bus.sensors[2]->line_time >= 150ms);  // its three attempts, counted as its own
}

TEST_CASE("a failing sensor held to its turn between rounds is logged once, not at each turn") {
  CapturedLog log(spdlog::level::warn);
  SchedulerBench bus;
  bus.line.retries_left_to_the_line = 2;  // its retries wait for the others' polls
  bus.add("a", 1, 10ms);
  bus.add("b", 2, 10ms);
  auto& dead = fake_driver(bus.add("dead", 3, 10ms));
  dead.poll_time = 20ms;
  bus.line.silent = [](const LineRequest& request) { return request.bytes.at(0) == 3; };
  bus.start();
  bus.io.run_for(1500ms);
  REQUIRE(dead.polls >= 3);  // probed again and again meanwhile
  std::size_t held = 0;
  for (const std::string& line : log.lines())
    if (line.find("sensor \"dead\" is failing: its attempts take one turn each") != std::string::npos)
      ++held;
  CHECK(held == 1);
}

TEST_CASE("a write to a sensor known offline is answered no response at once, and nothing is sent") {
  SchedulerBench bus;
  auto& sensor = bus.add("a", 1, 10s);
  auto& a = fake_driver(sensor);
  a.answers = false;
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls == 1 && bus.events.back() == "a poll end"; }));
  const std::uint64_t attempts = bus.line.stats().attempts;
  std::optional<WriteResult> result;
  bus.write(sensor, WriteTarget::filter, 3, SteadyClock::now() + 10s, result);
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error().kind == WriteErrorKind::no_response);
  CHECK(a.writes.empty());
  CHECK(bus.line.stats().attempts == attempts);
  CHECK(bus.scheduler.stats().writes_offline == 1);
}

TEST_CASE("a write to a sensor whose poll waits to retry after silence is answered at once") {
  SchedulerBench bus;
  bus.line.retries_left_to_the_line = 2;
  auto& sensor = bus.add("a", 1, 10s);
  auto& a = fake_driver(sensor);
  a.poll_time = 40ms;
  fake_driver(bus.add("b", 2, 10ms)).poll_time = 30ms;  // its polls go between a's attempts
  int attempts = 0;
  bus.line.on_attempt = [&](const LineRequest& request) {
    if (request.bytes.at(0) == 1) ++attempts;
  };
  bus.line.silent = [](const LineRequest& request) { return request.bytes.at(0) == 1; };
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return attempts == 1 && !bus.events.empty() &&
                                         bus.events.back() == "b poll"; }));
  CHECK_FALSE(known_offline(a.state()));  // not known yet: its poll has two attempts to go
  std::optional<WriteResult> result;
  const auto sent = SteadyClock::now();
  bus.write(sensor, WriteTarget::filter, 3, sent + 10s, result);
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(SteadyClock::now() - sent < 20ms);
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error().kind == WriteErrorKind::no_response);
  CHECK(a.writes.empty());
}

TEST_CASE("a poll that finds the tty gone does not back off: the sensor is polled at its period") {
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 1, 10ms));
  bus.line.open = false;
  bus.start();
  bus.io.run_for(300ms);
  // At its 10 ms period: about 30 polls; with the dead-sensor back-off (10, 20, 40, ... ms)
  // it would have had 5.
  CAPTURE(a.polls);
  CHECK(a.polls >= 12);
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
