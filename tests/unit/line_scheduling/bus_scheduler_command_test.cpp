// BusScheduler carrying commissioning commands' transactions (the control socket), on the
// bench of unit/support/scheduler_bench.h: each transaction is sent as the command
// gave it, lets the polls that fell due go between two of its turns, takes turns with
// forwarded requests, expires unsent at its deadline; and a sensor moved by a command is
// followed.
#include <doctest/doctest.h>

#include <optional>

#include "line_scheduling/bus_scheduler.h"
#include "unit/support/scheduler_bench.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

const WriteOrigin kTestOrigin{"control socket", "a test"};

TEST_CASE("a command's transaction is sent as given and its framer sees the reply") {
  std::optional<CommandExchangeResult> result;
  SchedulerBench bus;
  bus.command(9, SteadyClock::now() + 10s, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(result->done.has_value());
  CHECK_FALSE(result->expired);
  CHECK(result->generation == 1);
  REQUIRE(bus.sent.size() == 1);
  CHECK(bus.sent[0].bytes == std::vector<std::uint8_t>{0xC0, 9});
  CHECK(bus.sent[0].timeout == 7ms);
  CHECK(bus.sent[0].retries == 0);
  CHECK(bus.sent[0].settle == 3ms);
  CHECK(bus.framer.received == std::vector<std::uint8_t>{0xAC, 9});
  CHECK(bus.scheduler.stats().command_exchanges == 1);
}

TEST_CASE("between two of a command's transactions the polls that fell due go, so the sensors keep being polled") {
  std::vector<std::optional<CommandExchangeResult>> results(6);
  SchedulerBench bus;
  bus.add("a", 1, 10s);  // both due once, at start
  bus.add("b", 2, 10s);
  for (std::size_t i = 0; i < results.size(); ++i)
    bus.command(std::uint8_t(i), SteadyClock::now() + 10s, results[i]);
  bus.io.restart();
  bus.io.poll();  // every transaction queued before the loop starts
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return results.back().has_value(); }));
  // Both polls fell due before the first transaction ended: they go before the next.
  const BusEvents expected = {"command 0",  "a poll",    "a poll end", "b poll",
                              "b poll end", "command 1", "command 2",  "command 3"};
  REQUIRE(bus.events.size() >= expected.size());
  CHECK(BusEvents(bus.events.begin(), bus.events.begin() + 8) == expected);
}

TEST_CASE("a command and a pass-through client both waiting take turns with each other") {
  std::vector<std::optional<CommandExchangeResult>> commands(3);
  std::vector<std::optional<ForwardResult>> forwards(3);
  SchedulerBench bus;
  for (std::size_t i = 0; i < 3; ++i) {
    bus.command(std::uint8_t(i), SteadyClock::now() + 10s, commands[i]);
    bus.forward(std::uint8_t(i), SteadyClock::now() + 10s, forwards[i]);
  }
  bus.io.restart();
  bus.io.poll();
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return commands.back() && forwards.back(); }));
  CHECK(bus.events == BusEvents{"command 0", "forward 0", "command 1", "forward 1", "command 2",
                                "forward 2"});
}

TEST_CASE("a command's transaction still queued at its deadline expires and is never sent") {
  std::optional<CommandExchangeResult> result;
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 1, 10s));
  a.poll_time = 200ms;  // holds the line past the deadline
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls == 1; }));
  bus.command(1, SteadyClock::now() + 20ms, result);
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  CHECK(result->expired);
  CHECK(result->done.error() == LineError::timeout);
  CHECK(bus.sent.empty());
  CHECK(bus.scheduler.stats().command_exchanges_expired == 1);
}

TEST_CASE("a sensor a command moved is followed to its new address and polled there at once") {
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 223, 10s));
  bus.add("b", 5, 10s);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls == 1; }));
  CHECK(bus.scheduler.follow_address(223, 7, kTestOrigin) == std::optional<std::string>("a"));
  CHECK(a.state().bus_address == 7);
  REQUIRE(run_until(bus.io, [&] { return a.polls == 2; }));  // not after its 10 s period
  CHECK_FALSE(bus.scheduler.follow_address(223, 8, kTestOrigin).has_value());  // none at 223 now
  CHECK(bus.scheduler.follow_address(5, 6, kTestOrigin) == std::optional<std::string>("b"));
}

TEST_CASE("a sensor a command is moving is not polled until it is followed, released or the hold ends") {
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 223, 20ms));
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls >= 1; }));
  REQUIRE(bus.scheduler.hold(223, SteadyClock::now() + 10s) == std::optional<std::string>("a"));
  const int held_at = a.polls;
  bus.io.restart();
  bus.io.run_for(200ms);  // ten poll periods
  CHECK(a.polls <= held_at + 1);  // at most the poll already under way
  CHECK(bus.scheduler.follow_address(223, 7, kTestOrigin).has_value());
  REQUIRE(run_until(bus.io, [&] { return a.polls >= held_at + 3; }));

  // Released by the command, or by the hold's own end.
  REQUIRE(bus.scheduler.hold(7, SteadyClock::now() + 10s).has_value());
  bus.io.restart();
  bus.io.run_for(100ms);
  const int released_at = a.polls;
  bus.scheduler.release(7);
  REQUIRE(run_until(bus.io, [&] { return a.polls >= released_at + 2; }));
  REQUIRE(bus.scheduler.hold(7, SteadyClock::now() + 60ms).has_value());
  const int expiring_at = a.polls;
  REQUIRE(run_until(bus.io, [&] { return a.polls >= expiring_at + 3; }));
  CHECK_FALSE(bus.scheduler.hold(100, SteadyClock::now() + 10s).has_value());  // nobody there
}
