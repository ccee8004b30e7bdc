// SerialLine and a machine that is late to hand on what its tty received (serial/serial_line.h,
// "The machine's own lateness"): at a reply deadline the line asks how long this machine takes
// to hand on a byte (the delivery probe; here a scripted answer, as the kernel's worker cannot
// be held on purpose), and a machine that was behind starts the reply wait again rather than
// blame the device; one that holds the bytes past kMaxMachineHold gives the attempt up as
// overloaded. The real probe's byte comes through on this machine. No assertion is on how long
// anything took but lower bounds.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>
#include <deque>

#include "serial/delivery_probe.h"
#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::DeliveryProbe;
using tiltgate::LineError;
using tiltgate::SerialLineOptions;

namespace {

// The probe's answers, one per deadline, in order; "caught up at once" after the last.
struct ScriptedMachine {
  std::deque<std::optional<std::chrono::microseconds>> answers;
  int asked = 0;
  void install(tiltgate::SerialLine& line) {
    line.check_delivery_with(
        [this](std::chrono::milliseconds) -> asio::awaitable<std::optional<std::chrono::microseconds>> {
          ++asked;
          if (answers.empty()) co_return std::chrono::microseconds{50};
          const auto answer = answers.front();
          answers.pop_front();
          co_return answer;
        });
  }
};

// A device that answers `after` its request.
asio::awaitable<void> answers_after(FarEnd& far, Clock::duration after) {
  co_await far.receive(2);
  co_await pause(after);
  co_await far.send(octets(1, 2, 3, 4));
}

}  // namespace

TEST_CASE("a machine behind at the deadline starts the reply wait again: the reply is taken") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.retries = 0;
  });
  ScriptedMachine machine;
  machine.answers = {std::chrono::microseconds{8000}};  // 8 ms behind at the first deadline
  machine.install(*bench.line);
  CountFramer framer(4);
  const Result done = bench.exchange(request_of({1, 1}, &framer), answers_after(bench.far, 45ms));
  CHECK(done.has_value());
  CHECK(framer.bytes == Bytes{1, 2, 3, 4});
  CHECK(machine.asked == 1);
  CHECK(bench.line->last_timing().machine_held >= 8ms);
  CHECK(bench.line->last_timing().late_replies == 0);
  CHECK(bench.line->stats().machine_held == 1);
  CHECK(bench.line->stats().timeouts == 0);
}

TEST_CASE("a machine that kept up leaves the deadline as it was: a later reply is late") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 100ms;
    o.retries = 0;
  });
  ScriptedMachine machine;  // caught up at once, every time
  machine.install(*bench.line);
  CountFramer framer(4);
  const Result done = bench.exchange(request_of({1, 1}, &framer), answers_after(bench.far, 45ms));
  CHECK(done.error() == LineError::timeout);
  CHECK(machine.asked == 1);
  CHECK(bench.line->last_timing().late_replies == 1);
  CHECK(bench.line->stats().machine_held == 0);
  CHECK(bench.line->stats().timeouts == 1);
}

TEST_CASE("a machine still holding the bytes past the hold limit: overloaded, not retried") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 50ms;
    o.retries = 2;
  });
  ScriptedMachine machine;
  machine.answers = {std::nullopt};  // not through within the limit
  machine.install(*bench.line);
  CountFramer framer(4);
  auto device = [&]() -> asio::awaitable<void> { co_await bench.far.listen_silently(); };
  asio::co_spawn(bench.io, device(), asio::detached);
  const Result done = bench.transact(request_of({1, 1}, &framer));
  CHECK(done.error() == LineError::overloaded);
  CHECK(bench.far.received == 2);  // one request: no retry
  CHECK(bench.line->stats().overloaded == 1);
  CHECK(bench.line->stats().timeouts == 0);
}

TEST_CASE("the delivery probe's byte comes through this machine's tty layer") {
  asio::io_context io;
  DeliveryProbe probe(io.get_executor());
  std::optional<std::optional<std::chrono::microseconds>> first, second;
  asio::co_spawn(
      io,
      [&]() -> asio::awaitable<void> {
        first = co_await probe.measure(5s);
        second = co_await probe.measure(5s);
      },
      asio::detached);
  REQUIRE(run_until(io, [&] { return second.has_value(); }, 15s));
  CHECK(first->has_value());
  CHECK(second->has_value());
  probe.stop();
}
