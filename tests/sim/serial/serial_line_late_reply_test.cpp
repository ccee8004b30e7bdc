// SerialLine and replies that arrive after their attempt's time-out: they are discarded and
// counted, and the line sends nothing until the late-reply window has closed (the bus's reply
// wait plus the guard after the request) and a late burst then running has ended, so a late
// reply is never fed to the next transaction's framer. Timing assertions are lower bounds only.
#include <doctest/doctest.h>

#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>

#include "sim/support/emulated_timing.h"
#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::LineError;
using tiltgate::SerialLineOptions;

TEST_CASE("a reply after the time-out is counted late and not fed to the next transaction") {
  tiltgate::test::skip_if_emulated("the reply must come 50 ms after a 30 ms time-out, within the guard");
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 150ms;
  });
  CountFramer first(4);
  CountFramer second(4);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(2);
    co_await pause(80ms);  // 50 ms past the first request's time-out
    co_await bench.far.send(octets(0xEE, 0xEE, 0xEE, 0xEE));
    co_await bench.far.receive(2);
    co_await bench.far.send(octets(1, 2, 3, 4));
  };
  CHECK(bench.exchange(request_of({1, 1}, &first), device()).error() == LineError::timeout);
  CHECK(first.bytes.empty());
  CHECK(bench.line->last_timing().late_replies == 1);
  REQUIRE(bench.line->last_timing().late_delay.has_value());
  CHECK(*bench.line->last_timing().late_delay >= 30ms);
  CHECK_FALSE(bench.line->last_timing().reply_delay.has_value());

  CHECK(bench.transact(request_of({2, 2}, &second)).has_value());
  CHECK(second.bytes == Bytes{1, 2, 3, 4});
  CHECK(bench.line->last_timing().late_replies == 0);
  CHECK(bench.line->last_timing().reply_delay.has_value());
  CHECK(bench.line->stats().late_replies == 1);
  CHECK(bench.line->stats().timeouts == 1);
}

TEST_CASE("a retry waits until the late-reply window has closed and the late burst has ended") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 100ms;
    o.retries = 1;
  });
  CountFramer framer(2);
  Clock::time_point late_sent{};
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);
    co_await pause(115ms);  // its end runs past the window's close at 130 ms
    co_await bench.far.send(octets(0xEE));  // a late reply in two pieces 10 ms apart
    co_await pause(10ms);
    co_await bench.far.send(octets(0xEE));
    late_sent = Clock::now();
    co_await bench.far.receive(1);  // the retry
    co_await bench.far.send(octets(5, 6));
  };
  CHECK(bench.exchange(request_of({9}, &framer), device()).has_value());
  CHECK(framer.bytes == Bytes{5, 6});
  REQUIRE(bench.far.arrivals.size() == 2);
  // The window: reply wait + guard after the request; the burst: 20 ms quiet after its end.
  CHECK(bench.far.arrivals[1] - bench.far.arrivals[0] >= 130ms);
  CHECK(bench.far.arrivals[1] - late_sent >= 20ms);
  // One burst: its pieces were never 20 ms apart.
  CHECK(bench.line->last_timing().late_replies == 1);
  CHECK(bench.line->stats().attempts == 2);
}

TEST_CASE("a late reply to the first attempt after a retry succeeded stays in that transaction") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 60ms;
    o.retries = 1;
  });
  CountFramer framer(2);
  CountFramer next(2);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);  // silent to the first attempt during the guard
    co_await bench.far.receive(1);  // the retry is answered
    co_await bench.far.send(octets(5, 6));
    co_await pause(20ms);  // then a late answer to the first attempt
    co_await bench.far.send(octets(0xEE, 0xEE));
    co_await bench.far.receive(1);
    co_await bench.far.send(octets(7, 8));
  };
  CHECK(bench.exchange(request_of({9}, &framer), device()).has_value());
  CHECK(framer.bytes == Bytes{5, 6});
  CHECK(bench.line->last_timing().late_replies == 1);
  CHECK(bench.transact(request_of({10}, &next)).has_value());
  CHECK(next.bytes == Bytes{7, 8});
}

TEST_CASE("a line that never falls quiet holds the bus only for a bounded time") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 20ms;
    o.late_guard = 100ms;  // bounded by the longest wait, 2 s
  });
  CountFramer framer(64);
  bool babbling = true;
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);
    while (babbling) {
      co_await bench.far.send(octets(0xEE));
      co_await pause(10ms);
    }
  };
  const auto started = Clock::now();
  CHECK(bench.exchange(request_of({1}, &framer), device()).error() == LineError::timeout);
  babbling = false;
  CHECK(Clock::now() - started < 10s);
  CHECK(bench.line->last_timing().late_replies == 1);
}
