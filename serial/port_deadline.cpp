#include "serial/port_deadline.h"

namespace tiltgate {

PortDeadline::PortDeadline(boost::asio::any_io_executor executor,
                           boost::asio::posix::stream_descriptor& port)
    : port_(port), timer_(std::move(executor)) {
  state_->owner = this;
}

PortDeadline::~PortDeadline() {
  state_->owner = nullptr;
  timer_.cancel();
}

void PortDeadline::start(Clock::time_point deadline) {
  state_->running = true;
  state_->passed = false;
  state_->deadline = deadline;
  if (deadline < state_->armed_for) arm(deadline);
}

bool PortDeadline::finish() {
  state_->running = false;
  return state_->passed;
}

void PortDeadline::cancel() {
  ++state_->arming;
  state_->armed_for = Clock::time_point::max();
  timer_.cancel();
}

void PortDeadline::arm(Clock::time_point at) {
  const std::uint64_t arming = ++state_->arming;
  state_->armed_for = at;
  timer_.expires_at(at);  // a wait already pending completes as aborted, and is ignored
  timer_.async_wait([state = state_, arming](const boost::system::error_code& ec) {
    if (!ec) fired(state, arming);
  });
}

void PortDeadline::fired(const std::shared_ptr<State>& state, std::uint64_t arming) {
  if (state->owner == nullptr || arming != state->arming) return;
  state->armed_for = Clock::time_point::max();
  if (!state->running) return;  // nothing to end: the next operation sets the timer again
  if (Clock::now() < state->deadline) {
    state->owner->arm(state->deadline);  // a later operation than the one it was set for
    return;
  }
  state->passed = true;
  boost::system::error_code ignored;
  state->owner->port_.cancel(ignored);
}

}  // namespace tiltgate
