// ReadDeadline on a pseudo-terminal: one timer ends each read at its own deadline, whether it
// must be set sooner than it is (a short guard after a long reply time-out) or is found set
// for an earlier read (polls back to back). Timing assertions leave room for a busy machine.
#include "serial/read_deadline.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <utility>

#include "serial/pseudo_terminal.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using tiltgate::PseudoTerminal;
using tiltgate::ReadDeadline;
using Clock = std::chrono::steady_clock;

namespace {

// The slave side of a pty, read through asio as SerialLine reads its port; the master side
// writes what the "device" sends.
struct Pty {
  Pty()
      : pty(std::move(*PseudoTerminal::open())),
        port(io, ::open(pty.slave_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK)) {}

  void device_sends(std::uint8_t byte) { REQUIRE(::write(pty.master_fd(), &byte, 1) == 1); }

  asio::io_context io;
  PseudoTerminal pty;
  asio::posix::stream_descriptor port;
};

// One guarded read as SerialLine::read_before makes it.
struct Read {
  bool done = false;
  bool cancelled = false;
  bool passed = false;
  Clock::time_point ended{};
};

void start_read(Pty& pty, ReadDeadline& deadline, Clock::time_point at, Read& read,
                std::array<std::uint8_t, 16>& buffer) {
  deadline.start(at);
  pty.port.async_read_some(asio::buffer(buffer),
                           [&](const boost::system::error_code& ec, std::size_t) {
                             read.done = true;
                             read.cancelled = ec == asio::error::operation_aborted;
                             read.passed = deadline.finish();
                             read.ended = Clock::now();
                           });
}

void run_until_done(Pty& pty, const Read& read, std::chrono::milliseconds limit) {
  const auto give_up = Clock::now() + limit;
  while (!read.done && Clock::now() < give_up) pty.io.run_for(5ms);
}

}  // namespace

TEST_CASE("a read still waiting at its deadline is cancelled, and finish() says so") {
  Pty pty;
  ReadDeadline deadline(pty.io.get_executor(), pty.port);
  std::array<std::uint8_t, 16> buffer{};
  Read read;
  const auto started = Clock::now();
  start_read(pty, deadline, started + 30ms, read, buffer);
  run_until_done(pty, read, 2000ms);
  REQUIRE(read.done);
  CHECK(read.cancelled);
  CHECK(read.passed);
  CHECK(read.ended - started >= 30ms);
}

TEST_CASE("a read answered in time is not cut short, and the timer left set ends no later read") {
  Pty pty;
  ReadDeadline deadline(pty.io.get_executor(), pty.port);
  std::array<std::uint8_t, 16> buffer{};
  Read first;
  const auto started = Clock::now();
  start_read(pty, deadline, started + 40ms, first, buffer);
  pty.device_sends(0x42);
  run_until_done(pty, first, 2000ms);
  REQUIRE(first.done);
  CHECK_FALSE(first.cancelled);
  CHECK_FALSE(first.passed);

  // The next read is due later than the timer is set for (as each poll on a busy bus): when
  // the timer fires at the first deadline it must find this read not yet due and wait on.
  Read second;
  start_read(pty, deadline, started + 250ms, second, buffer);
  run_until_done(pty, second, 3000ms);
  REQUIRE(second.done);
  CHECK(second.cancelled);
  CHECK(second.passed);
  CHECK(second.ended - started >= 250ms);
}

TEST_CASE("a deadline sooner than the timer is set for ends its read on time") {
  Pty pty;
  ReadDeadline deadline(pty.io.get_executor(), pty.port);
  std::array<std::uint8_t, 16> buffer{};
  Read first;
  const auto started = Clock::now();
  start_read(pty, deadline, started + 10s, first, buffer);  // a long reply time-out, answered
  pty.device_sends(0x42);
  run_until_done(pty, first, 2000ms);
  REQUIRE(first.done);
  CHECK_FALSE(first.passed);

  Read second;  // a short guard: must not wait for the timer set 10 s out
  const auto second_started = Clock::now();
  start_read(pty, deadline, second_started + 30ms, second, buffer);
  run_until_done(pty, second, 5000ms);
  REQUIRE(second.done);
  CHECK(second.passed);
  CHECK(second.ended - second_started >= 30ms);
  CHECK(second.ended - second_started < 5000ms);
}

TEST_CASE("a deadline destroyed with its timer set leaves the port alone") {
  Pty pty;
  std::array<std::uint8_t, 16> buffer{};
  Read read;
  {
    auto deadline = std::make_unique<ReadDeadline>(pty.io.get_executor(), pty.port);
    start_read(pty, *deadline, Clock::now() + 20ms, read, buffer);
    deadline->finish();
    // The read's handler would call finish() on a destroyed object: it is given data first.
    pty.device_sends(0x42);
    run_until_done(pty, read, 2000ms);
  }
  REQUIRE(read.done);
  CHECK_FALSE(read.cancelled);
  // The timer's handler runs after the object is gone; it must not cancel anything.
  std::array<std::uint8_t, 16> more{};
  bool later_done = false;
  pty.port.async_read_some(asio::buffer(more), [&](const boost::system::error_code&, std::size_t) {
    later_done = true;
  });
  pty.io.run_for(60ms);
  CHECK_FALSE(later_done);  // still waiting: no stray cancel reached it
  pty.port.cancel();
  pty.io.run_for(10ms);
  CHECK(later_done);
}

TEST_CASE("a cancelled deadline leaves its event loop nothing to wait for") {
  Pty pty;
  ReadDeadline deadline(pty.io.get_executor(), pty.port);
  std::array<std::uint8_t, 16> buffer{};
  Read read;
  start_read(pty, deadline, Clock::now() + 10s, read, buffer);
  pty.device_sends(0x42);
  run_until_done(pty, read, 2000ms);
  REQUIRE(read.done);
  deadline.cancel();  // as SerialLine::stop() does; the timer was set 10 s out
  const auto started = Clock::now();
  pty.io.restart();
  pty.io.run();  // returns once nothing is pending
  CHECK(Clock::now() - started < 2s);
}
