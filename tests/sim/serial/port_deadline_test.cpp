// PortDeadline on a pseudo-terminal, guarding reads: one timer ends each read at its own deadline, whether it
// must be set sooner than it is (a short guard after a long reply time-out) or is found set
// for an earlier read (polls back to back). Timing assertions leave room for a busy machine.
#include "serial/port_deadline.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <utility>

#include "serial/pseudo_terminal.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using tiltgate::PseudoTerminal;
using tiltgate::PortDeadline;
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

// One guarded read as SerialLine::read_before makes it, and how it ended.
struct Read {
  bool done = false;
  bool cancelled = false;
  bool passed = false;
  Clock::time_point ended{};
};

// A pty and one line's deadline on it: reads the device answers at once, or never.
struct Reads {
  Read answered(Clock::time_point deadline_at) { return read(deadline_at, true, 2000ms); }
  Read unanswered(Clock::time_point deadline_at, std::chrono::milliseconds limit) {
    return read(deadline_at, false, limit);
  }

  Read read(Clock::time_point deadline_at, bool answer, std::chrono::milliseconds limit) {
    Read read;
    deadline.start(deadline_at);
    pty.port.async_read_some(asio::buffer(buffer),
                             [&](const boost::system::error_code& ec, std::size_t) {
                               read.done = true;
                               read.cancelled = ec == asio::error::operation_aborted;
                               read.passed = deadline.finish();
                               read.ended = Clock::now();
                             });
    if (answer) pty.device_sends(0x42);
    const auto give_up = Clock::now() + limit;
    while (!read.done && Clock::now() < give_up) pty.io.run_for(5ms);
    REQUIRE(read.done);
    return read;
  }

  Pty pty;
  PortDeadline deadline{pty.io.get_executor(), pty.port};
  std::array<std::uint8_t, 16> buffer{};
};

// The read was ended by its deadline, `after` from `started` or later.
void check_ended_by_deadline(const Read& read, Clock::time_point started,
                             std::chrono::milliseconds after) {
  CHECK(read.cancelled);
  CHECK(read.passed);
  CHECK(read.ended - started >= after);
}

}  // namespace

TEST_CASE("a read still waiting at its deadline is cancelled, and finish() says so") {
  Reads reads;
  const auto started = Clock::now();
  check_ended_by_deadline(reads.unanswered(started + 30ms, 2000ms), started, 30ms);
}

TEST_CASE("a read answered in time is not cut short, and the timer left set ends no later read") {
  Reads reads;
  const auto started = Clock::now();
  const Read first = reads.answered(started + 40ms);
  CHECK_FALSE(first.cancelled);
  CHECK_FALSE(first.passed);

  // The next read is due later than the timer is set for (as each poll on a busy bus): when
  // the timer fires at the first deadline it must find this read not yet due and wait on.
  check_ended_by_deadline(reads.unanswered(started + 250ms, 3000ms), started, 250ms);
}

TEST_CASE("a deadline sooner than the timer is set for ends its read on time") {
  Reads reads;
  CHECK_FALSE(reads.answered(Clock::now() + 10s).passed);  // a long reply time-out, answered

  // A short guard: must not wait for the timer set 10 s out.
  const auto started = Clock::now();
  check_ended_by_deadline(reads.unanswered(started + 30ms, 5000ms), started, 30ms);
}

TEST_CASE("a deadline destroyed with its timer set leaves the port alone") {
  Pty pty;
  {
    PortDeadline deadline(pty.io.get_executor(), pty.port);
    deadline.start(Clock::now() + 20ms);
    deadline.finish();
  }
  // The timer's handler runs after the object is gone; it must not cancel anything.
  std::array<std::uint8_t, 16> buffer{};
  bool done = false;
  pty.port.async_read_some(asio::buffer(buffer),
                           [&](const boost::system::error_code&, std::size_t) { done = true; });
  pty.io.run_for(60ms);
  CHECK_FALSE(done);  // still waiting: no stray cancel reached it
  pty.port.cancel();
  pty.io.run_for(10ms);
  CHECK(done);
}

TEST_CASE("a cancelled deadline leaves its event loop nothing to wait for") {
  Reads reads;
  reads.answered(Clock::now() + 10s);
  reads.deadline.cancel();  // as SerialLine::stop() does; the timer was set 10 s out
  const auto started = Clock::now();
  reads.pty.io.restart();
  reads.pty.io.run();  // returns once nothing is pending
  CHECK(Clock::now() - started < 2s);
}
