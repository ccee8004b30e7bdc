// The deadline of a line's reads and writes: an operation on the port still waiting at its
// deadline is cancelled, as a timer per operation would do it (Boost 1.74 has no awaitable
// operators or cancel_after to race one against a timer), but with one timer that is set again
// only when it fires or when an operation must end sooner than it is set for. A line has one
// operation on its port at a time.
//
// Why not a timer per read: a new reply deadline is always the event loop's earliest, so
// arming one cost a timerfd_settime on every poll, and cancelling it a handler of its own. On
// a saturated bus a poll's deadline lies ~50 ms out and moves ~2.5 ms later with each poll, so
// this timer fires about once per reply time-out, finds the read in flight due later, and is
// set for that (docs/performance.md, "The bus as the gateway runs it").
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>

namespace tiltgate {

class PortDeadline {
 public:
  using Clock = std::chrono::steady_clock;

  // `port` is the descriptor whose pending operation is cancelled at a deadline; it outlives
  // this.
  PortDeadline(boost::asio::any_io_executor executor, boost::asio::posix::stream_descriptor& port);
  ~PortDeadline();
  PortDeadline(const PortDeadline&) = delete;
  PortDeadline& operator=(const PortDeadline&) = delete;

  // An operation on the port (a read, a write) starts now and must end by `deadline`.
  void start(Clock::time_point deadline);
  // That operation ended (completed, failed or cancelled): true if its deadline cancelled it.
  bool finish();
  // Unsets the timer, so that a stopped line leaves its event loop nothing to wait for.
  void cancel();

 private:
  // Shared with the timer's handler, which may run after this object is gone (`owner` null).
  struct State {
    PortDeadline* owner = nullptr;
    bool running = false;  // an operation is under this deadline
    bool passed = false;
    Clock::time_point deadline{};
    Clock::time_point armed_for = Clock::time_point::max();  // max: the timer is not waiting
    std::uint64_t arming = 0;  // which async_wait is current; earlier ones are ignored
  };

  void arm(Clock::time_point at);
  static void fired(const std::shared_ptr<State>& state, std::uint64_t arming);

  boost::asio::posix::stream_descriptor& port_;
  boost::asio::steady_timer timer_;
  std::shared_ptr<State> state_ = std::make_shared<State>();
};

}  // namespace tiltgate
