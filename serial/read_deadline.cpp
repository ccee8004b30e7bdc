#include "serial/read_deadline.h"

namespace tiltgate {

ReadDeadline::ReadDeadline(boost::asio::any_io_executor executor,
                           boost::asio::posix::stream_descriptor& port)
    : port_(port), timer_(std::move(executor)) {
  state_->owner = this;
}

ReadDeadline::~ReadDeadline() {
  state_->owner = nullptr;
  timer_.cancel();
}

void ReadDeadline::start(Clock::time_point deadline) {
  state_->reading = true;
  state_->passed = false;
  state_->deadline = deadline;
  if (deadline < state_->armed_for) arm(deadline);
}

bool ReadDeadline::finish() {
  state_->reading = false;
  return state_->passed;
}

void ReadDeadline::cancel() {
  ++state_->arming;
  state_->armed_for = Clock::time_point::max();
  timer_.cancel();
}

void ReadDeadline::arm(Clock::time_point at) {
  const std::uint64_t arming = ++state_->arming;
  state_->armed_for = at;
  timer_.expires_at(at);  // a wait already pending completes as aborted, and is ignored
  timer_.async_wait([state = state_, arming](const boost::system::error_code& ec) {
    if (!ec) fired(state, arming);
  });
}

void ReadDeadline::fired(const std::shared_ptr<State>& state, std::uint64_t arming) {
  if (state->owner == nullptr || arming != state->arming) return;
  state->armed_for = Clock::time_point::max();
  if (!state->reading) return;  // nothing to end: the next read sets the timer again
  if (Clock::now() < state->deadline) {
    state->owner->arm(state->deadline);  // a later read than the one it was set for
    return;
  }
  state->passed = true;
  boost::system::error_code ignored;
  state->owner->port_.cancel(ignored);
}

}  // namespace tiltgate
