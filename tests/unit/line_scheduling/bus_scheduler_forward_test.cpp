// BusScheduler forwarding requests to devices passed through ([[bus]] pass_through), on the
// bench of unit/support/scheduler_bench.h, whose fake protocol frames a PDU as slave + PDU and
// takes any bytes back as the reply: the polls that fell due go between two forwarded
// exchanges, a write goes first, the queue is bounded with a share for each client, clients
// take turns, queued requests expire, and each exchange is sent once.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <optional>

#include "line_scheduling/bus_scheduler.h"
#include "unit/support/scheduler_bench.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

TEST_CASE("a forwarded request is sent once to its slave and answered with the reply PDU") {
  SchedulerBench bus;
  std::optional<ForwardResult> result;
  bus.forward(3, SteadyClock::now() + 10s, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  REQUIRE(result->has_value());
  CHECK(**result == std::vector<std::uint8_t>{3, 0, 1});
  REQUIRE(bus.sent.size() == 1);
  CHECK(bus.sent[0].bytes == std::vector<std::uint8_t>{30, 3, 0, 1});
  CHECK(bus.sent[0].retries == 0);  // never twice: the client retries
  CHECK(bus.sent[0].timeout == 0ms);  // the bus's reply time-out
  CHECK(bus.scheduler.stats().forwarded == 1);
}

TEST_CASE("a forwarded request nobody answers fails as no response, without a retry") {
  SchedulerBench bus;
  bus.device_answers = false;
  std::optional<ForwardResult> result;
  bus.forward(3, SteadyClock::now() + 10s, result);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error() == ForwardFailure::no_response);
  CHECK(bus.line.stats().attempts == 1);
  CHECK(bus.scheduler.stats().forward_timeouts == 1);
  CHECK(bus.scheduler.stats().forwarded == 0);
}

TEST_CASE("between two forwarded exchanges the polls that fell due meanwhile go") {
  SchedulerBench bus;
  bus.add("a", 1, 10s);  // both due once, at start
  bus.add("b", 2, 10s);
  std::vector<std::optional<ForwardResult>> results(10);
  for (std::size_t i = 0; i < results.size(); ++i)
    bus.forward(std::uint8_t(i), SteadyClock::now() + 10s, results[i]);
  bus.io.restart();
  bus.io.poll();  // every forward queued before the loop starts
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return results.back().has_value(); }));
  // Both polls fell due before the first exchange ended: they go before the next.
  const BusEvents expected = {"forward 0",  "a poll",    "a poll end", "b poll",
                              "b poll end", "forward 1", "forward 2",  "forward 3"};
  REQUIRE(bus.events.size() >= expected.size());
  CHECK(BusEvents(bus.events.begin(), bus.events.begin() + 8) == expected);
  CHECK(bus.scheduler.stats().forwarded == 10);
}

TEST_CASE("a sensor due all the time and a hammered pass-through unit share the bus evenly") {
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 1, 10ms));
  a.poll_time = 20ms;  // longer than its period: always due
  int answered = 0;
  std::vector<std::optional<ForwardResult>> results(20);
  // A client that sends its next request as soon as the last one is answered.
  asio::co_spawn(
      bus.io,
      [&]() -> asio::awaitable<void> {
        for (int i = 0; i < 20; ++i) {
          std::vector<std::uint8_t> pdu{3, 0, 1};
          auto reply = co_await bus.scheduler.forward(30, std::move(pdu), SteadyClock::now() + 10s);
          if (reply) ++answered;
        }
      },
      asio::detached);
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return answered == 20; }));
  // Every forward but the first waits for exactly one poll.
  CHECK(a.polls >= 19);
  CHECK(a.polls <= 21);
}

TEST_CASE("a write goes ahead of a forwarded request queued before it") {
  SchedulerBench bus;
  auto& sensor = bus.add("a", 1, 10s);
  std::optional<ForwardResult> forwarded;
  std::optional<WriteResult> written;
  bus.forward(3, SteadyClock::now() + 10s, forwarded);
  bus.write(sensor, WriteTarget::filter, 3, SteadyClock::now() + 10s, written);
  bus.io.restart();
  bus.io.poll();
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return forwarded.has_value() && written.has_value(); }));
  // The poll that fell due before the write ended goes before the next other turn.
  CHECK(bus.events ==
        BusEvents{"a write", "a write end", "a poll", "a poll end", "forward 3"});
}

TEST_CASE("a full forward queue answers busy at once") {
  // Declared before the bus: its destructor ends the queued requests, which then set these.
  std::vector<std::optional<ForwardResult>> queued(BusScheduler::kMaxQueuedForwards);
  SchedulerBench bus;  // not started: nothing leaves the queue
  for (auto& result : queued) bus.forward(1, SteadyClock::now() + 10s, result);
  std::optional<ForwardResult> one_more;
  bus.forward(2, SteadyClock::now() + 10s, one_more);
  REQUIRE(run_until(bus.io, [&] { return one_more.has_value(); }));
  REQUIRE_FALSE(one_more->has_value());
  CHECK(one_more->error() == ForwardFailure::busy);
  CHECK(bus.scheduler.stats().forwards_busy == 1);
  for (const auto& result : queued) CHECK_FALSE(result.has_value());  // still waiting
}

TEST_CASE("a client that filled the forward queue leaves room for another client's request") {
  std::vector<std::optional<ForwardResult>> greedy(BusScheduler::kMaxQueuedForwards + 4);
  std::optional<ForwardResult> other, greedy_more;
  SchedulerBench bus;  // not started: nothing leaves the queue
  for (auto& result : greedy) bus.forward(1, SteadyClock::now() + 10s, result, 7);
  bus.forward(2, SteadyClock::now() + 10s, other, 9);
  bus.forward(1, SteadyClock::now() + 10s, greedy_more, 7);
  REQUIRE(run_until(bus.io, [&] { return greedy_more.has_value(); }));
  // The greedy client got the queue's 32 places and was refused the 4 after them, and again
  // now that another client waits: it holds more than its half.
  CHECK(bus.scheduler.stats().forwards_busy == 5);
  CHECK_FALSE(other.has_value());  // queued, waiting for its turn
  REQUIRE_FALSE(greedy_more->has_value());
  CHECK(greedy_more->error() == ForwardFailure::busy);
}

TEST_CASE("two clients' forwarded requests take turns, however many one of them queued") {
  std::vector<std::optional<ForwardResult>> greedy(6);
  std::optional<ForwardResult> other;
  SchedulerBench bus;
  for (std::size_t i = 0; i < greedy.size(); ++i)
    bus.forward(std::uint8_t(i), SteadyClock::now() + 10s, greedy[i], 7);
  bus.forward(100, SteadyClock::now() + 10s, other, 9);
  bus.io.restart();
  bus.io.poll();  // all queued before the loop starts
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return other.has_value(); }));
  // Client 9 is second: one of client 7's, then its own, before 7's others.
  REQUIRE(bus.events.size() >= 2);
  CHECK(bus.events[1] == "forward 100");
}

TEST_CASE("a forwarded request still queued at its deadline fails and is never sent") {
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 1, 10s));
  a.poll_time = 1000ms;  // holds the line far past the request's deadline
  std::optional<ForwardResult> result;
  a.on_poll = [&] { bus.forward(3, SteadyClock::now() + 20ms, result); };
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return result.has_value(); }));
  REQUIRE_FALSE(result->has_value());
  CHECK(result->error() == ForwardFailure::expired);
  bus.io.restart();
  bus.io.run_for(1200ms);  // the poll ends; the expired request must not follow it
  CHECK(bus.sent.empty());
  CHECK(bus.scheduler.stats().forwards_expired == 1);
}
