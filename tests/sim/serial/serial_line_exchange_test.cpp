// SerialLine exchanges against a scripted far end on a pseudo-terminal: chunked replies,
// time-outs and retries, the quiet gap, the adapter's echo, stale input and stop. Timing
// assertions are lower bounds only.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::LineError;
using tiltgate::LineRequest;
using tiltgate::Parity;
using tiltgate::SerialLineOptions;
using tiltgate::SerialLine;

TEST_CASE("a transaction before start finds the line closed") {
  asio::io_context io;
  SerialLine line(io.get_executor(), options_for("/nonexistent/tty"));
  CHECK(transact(io, line, request_of({1}, nullptr)).error() == LineError::closed);
  CHECK(line.generation() == 0);
}

TEST_CASE("a reply split into many chunks is assembled by the framer") {
  Bench bench;
  CountFramer framer(6);
  const Bytes reply{10, 11, 12, 13, 14, 15};
  auto device = [&]() -> asio::awaitable<void> {
    CHECK(co_await bench.far.receive(3) == octets(1, 2, 3));
    for (std::size_t i = 0; i < reply.size(); ++i) {
      co_await bench.far.send(octets(reply[i]));
      // The next byte only once the line has fed this one, so each is a chunk of its own.
      co_await eventually([&] { return framer.bytes.size() == i + 1; });
    }
  };
  CHECK(bench.exchange(request_of({1, 2, 3}, &framer), device()).has_value());
  CHECK(framer.bytes == reply);
  CHECK(framer.feeds == 6);
  CHECK(bench.line->stats().attempts == 1);
  CHECK(bench.line->stats().timeouts == 0);
}

TEST_CASE("a silent device times out after every retry, each attempt counted") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 20ms;
    o.retries = 2;
  });
  CountFramer framer(1);
  asio::co_spawn(bench.io, bench.far.listen_silently(), asio::detached);
  CHECK(bench.transact(request_of({1, 2, 3}, &framer)).error() == LineError::timeout);
  LineRequest once = request_of({4, 5, 6}, &framer);
  once.retries = 0;  // e.g. Set Address, which must not run twice
  CHECK(bench.transact(std::move(once)).error() == LineError::timeout);
  CHECK(run_until(bench.io, [&] { return bench.far.received == 12; }));
  CHECK(bench.line->stats().attempts == 4);
  CHECK(bench.line->stats().timeouts == 4);
  CHECK(bench.line->stats().io_errors == 0);
  CHECK(bench.line->is_open());
}

TEST_CASE("a retry starts the reply afresh") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 300ms;  // the whole reply must make it within one attempt, even on a busy machine
    o.retries = 1;
  });
  CountFramer framer(4);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(2);
    co_await bench.far.send(octets(0xAA, 0xBB));  // half a reply, then silence
    co_await bench.far.receive(2);
    co_await bench.far.send(octets(1, 2, 3, 4));
  };
  CHECK(bench.exchange(request_of({7, 8}, &framer), device()).has_value());
  CHECK(framer.bytes == Bytes{1, 2, 3, 4});
  CHECK(bench.line->stats().attempts == 2);
  CHECK(bench.line->stats().timeouts == 1);
}

TEST_CASE("the quiet gap and a request's settle time separate master packets") {
  // Each packet's departure is noted by the write hook, right as its write completes; the
  // next packet's arrival is noted by the far end. The line also waits out the 12.5 ms a
  // 12-byte packet takes at 9600 baud, which covers the hook's few microseconds of lateness.
  // (Arrival-to-arrival would not do: the far end may read the first packet late.)
  Bench bench([](SerialLineOptions& o) {
    o.baud = 9600;
    o.gap = 20ms;
  });
  std::vector<Clock::time_point> departures;
  bench.line->observe_writes([&](std::span<const std::uint8_t>, Parity,
                                 const tiltgate::TtySettings&) {
    departures.push_back(Clock::now());
  });
  const Bytes packet(12, 0x42);
  auto device = [&]() -> asio::awaitable<void> {
    for (int i = 0; i < 3; ++i) co_await bench.far.receive(packet.size());
  };
  CHECK(bench.exchange(request_of(packet, nullptr), device()).has_value());
  LineRequest settling = request_of(packet, nullptr);
  settling.settle = 50ms;  // Rieker: 50 ms after Set Address
  CHECK(bench.transact(std::move(settling)).has_value());
  CHECK(bench.transact(request_of(packet, nullptr)).has_value());
  REQUIRE(run_until(bench.io, [&] { return bench.far.arrivals.size() == 3; }));
  REQUIRE(departures.size() == 3);
  CHECK(bench.far.arrivals[1] - departures[0] >= 20ms);
  CHECK(bench.far.arrivals[2] - departures[1] >= 70ms);
  CHECK(bench.line->stats().attempts == 3);
}

TEST_CASE("the adapter's echo of the request is skipped before the reply") {
  Bench bench([](SerialLineOptions& o) { o.echo = true; });
  const Bytes request{0x01, 0x02, 0x03, 0x04};
  LineEndFramer framer;
  auto device = [&]() -> asio::awaitable<void> {
    // Echo and reply in one chunk, then echo and reply apart.
    Bytes echo_and_reply = co_await bench.far.receive(request.size());
    for (std::uint8_t b : bytes_of("first\n")) echo_and_reply.push_back(b);
    co_await bench.far.send(echo_and_reply);
    co_await bench.far.send(co_await bench.far.receive(request.size()));
    co_await bench.far.send(bytes_of("second\n"));
  };
  CHECK(bench.exchange(request_of(request, &framer), device()).has_value());
  CHECK(framer.text == "first\n");
  CHECK(bench.transact(request_of(request, &framer)).has_value());
  CHECK(framer.text == "second\n");
  CHECK(bench.line->echo_mismatches() == 0);
}

TEST_CASE("an echo that differs from the request fails the attempt as a collision") {
  Bench bench([](SerialLineOptions& o) {
    o.echo = true;
    o.retries = 1;
  });
  LineEndFramer framer;
  auto device = [&]() -> asio::awaitable<void> {
    for (int attempt = 0; attempt < 2; ++attempt) {
      Bytes garbled = co_await bench.far.receive(3);
      garbled[1] ^= 0xFF;
      garbled.push_back('\n');
      co_await bench.far.send(garbled);
    }
  };
  CHECK(bench.exchange(request_of(bytes_of("abc"), &framer), device()).error() ==
        LineError::timeout);
  CHECK(bench.line->echo_mismatches() == 2);
  CHECK(bench.line->stats().attempts == 2);
  CHECK(bench.line->stats().io_errors == 0);
}

TEST_CASE("input received before a request is discarded") {
  Bench bench;
  LineEndFramer framer;
  // Wait, through a second descriptor on the slave, until the stale bytes have reached it.
  const int watcher = ::open(bench.pty.slave_path().c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK);
  REQUIRE(watcher >= 0);
  const std::string junk = "late reply\n";
  REQUIRE(::write(bench.far.native(), junk.data(), junk.size()) == ssize_t(junk.size()));
  pollfd p{watcher, POLLIN, 0};
  REQUIRE(::poll(&p, 1, 2000) == 1);
  ::close(watcher);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);
    co_await bench.far.send(bytes_of("fresh\n"));
  };
  CHECK(bench.exchange(request_of(bytes_of("?"), &framer), device()).has_value());
  CHECK(framer.text == "fresh\n");
}

TEST_CASE("a packet the port does not take within its wire time and a second fails as stalled") {
  // Nobody reads the far end: the pty's buffer fills and the rest of the packet waits, under
  // the stall deadline (the line's one deadline timer, also set for the reads before it).
  Bench bench([](SerialLineOptions& o) { o.baud = 4000000; });  // 256 kB: 0.64 s on the wire
  CountFramer framer(1);
  const auto started = Clock::now();
  CHECK(bench.transact(request_of(Bytes(256 * 1024, 0x55), &framer)).error() == LineError::io);
  CHECK(Clock::now() - started >= 1600ms);
  CHECK(bench.line->stats().io_errors == 1);
}

TEST_CASE("stop cancels a pending transaction and every later one") {
  Bench bench([](SerialLineOptions& o) { o.timeout = 10000ms; });
  CountFramer framer(1);
  auto stopper = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);  // the request is out: the line now waits for a reply
    bench.line->stop();
  };
  CHECK(bench.exchange(request_of({1}, &framer), stopper()).error() == LineError::cancelled);
  CHECK(bench.transact(request_of({1}, &framer)).error() == LineError::cancelled);
  CHECK_FALSE(bench.line->is_open());
  CHECK(bench.line->stats().timeouts == 0);
}
