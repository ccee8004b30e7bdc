#include "line_scheduling/shared_line.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "line_scheduling/exception_text.h"
#include "line_scheduling/line_claimant.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// A sensor that is offline (its polls are probes at the back-off's pace) or answers late: each
// of its attempts is a turn of its own, one between rounds (line_scheduling/line_turns.h).
bool failing(const GatewaySensor& sensor) {
  const SensorState& state = sensor.driver->state();
  return known_offline(state) || state.answers_late;
}

}  // namespace

SharedLine::SharedLine(asio::any_io_executor executor, Line& line, std::string name)
    : executor_(executor), line_(line), name_(std::move(name)), wake_(executor) {}

SharedLine::~SharedLine() { stop(); }

asio::awaitable<void> SharedLine::run() {
  running_ = true;
  dispatch();
  while (!stopping_) {
    if (failure_) {
      co_await restart();
      continue;
    }
    boost::system::error_code ec;
    co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (ec || stopping_ || failure_) continue;  // set anew, stopped, or failed
    // A due time came: nothing to wake for again until dispatch() says.
    wake_.expires_at(SteadyClock::time_point::max());
    dispatch();
  }
}

void SharedLine::fail(std::exception_ptr failure) {
  failure_ = failure;
  wake_.cancel();  // run() restarts
}

asio::awaitable<void> SharedLine::restart() {
  ++restarts_;
  const std::string what = exception_text(failure_);
  std::size_t refused = 0;
  for (LineClaimant* claimant : std::vector(waiting_))
    if (claimant->claim_.kind != TurnKind::poll) {
      refuse(*claimant);
      ++refused;
    }
  const auto now = SteadyClock::now();
  if (!failure_logged_at_ || now - *failure_logged_at_ >= kFailureLogInterval) {
    failure_logged_at_ = now;
    spdlog::error("{}: choosing the line's next turn failed: {}; {} waiting write(s), forwarded "
                  "request(s) and command(s) refused, turns given again in {} s ({} failure(s) "
                  "so far: tiltgate_bus_restarts_total)",
                  name_, what, refused, kRestartPause.count(), restarts_);
  }
  wake_.expires_after(kRestartPause);
  boost::system::error_code ec;
  co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  wake_.expires_at(SteadyClock::time_point::max());
  failure_ = nullptr;
  dispatch();
}

void SharedLine::stop() {
  if (stopping_) return;
  stopping_ = true;
  wake_.cancel();
  for (LineClaimant* claimant : std::vector(waiting_)) refuse(*claimant);
  for (LineClaimant* claimant : engaged_) claimant->shared_ = nullptr;
  if (holder_ != nullptr) holder_->shared_ = nullptr;
  holder_ = nullptr;
  engaged_.clear();
}

void SharedLine::keep_only_writes() {
  only_writes_ = true;
  for (LineClaimant* claimant : std::vector(waiting_))
    if (claimant->claim_.kind != TurnKind::write) refuse(*claimant);
  dispatch();
}

void SharedLine::reschedule(LineClaimant& claimant, SteadyClock::time_point due) {
  claimant.claim_.due = due;
  dispatch();
}

void SharedLine::refuse(LineClaimant& claimant) {
  std::erase(waiting_, &claimant);
  claimant.state_ = LineClaimant::State::idle;
  claimant.outcome_ = TurnGrant::refused;
  if (stopping_) claimant.shared_ = nullptr;  // nothing of it touches this any more
  claimant.wake_.cancel();
}

SharedLine::ForwardsWaiting SharedLine::forwards_waiting(std::uint64_t client) const {
  ForwardsWaiting forwards;
  std::vector<std::uint64_t> clients{client};
  for (const LineClaimant* waiting : waiting_) {
    if (waiting->claim_.kind != TurnKind::forward) continue;
    ++forwards.queued;
    if (waiting->claim_.client == client) ++forwards.from_client;
    if (std::find(clients.begin(), clients.end(), waiting->claim_.client) == clients.end())
      clients.push_back(waiting->claim_.client);
  }
  forwards.clients = clients.size();
  return forwards;
}

void SharedLine::enqueue(LineClaimant& claimant) {
  if (stopping_ || (only_writes_ && claimant.claim_.kind != TurnKind::write)) {
    refuse(claimant);
    return;
  }
  claimant.claim_.order = next_order_++;
  waiting_.push_back(&claimant);
  dispatch();
}

void SharedLine::withdraw(LineClaimant& claimant) {
  std::erase(waiting_, &claimant);
  claimant.state_ = LineClaimant::State::idle;
  dispatch();
}

void SharedLine::end_turn(LineClaimant& claimant) {
  const auto now = SteadyClock::now();
  const auto held = now - claimant.turn_started_;
  busy_ += held;
  if (claimant.sensor_ != nullptr) claimant.sensor_->line_time += held;
  turns_.ended(claimant.claim_, now, held);
  holder_ = nullptr;
  claimant.state_ = LineClaimant::State::idle;
  dispatch();
}

void SharedLine::disengage(LineClaimant& claimant) {
  std::erase(engaged_, &claimant);
  claimant.engaged_ = false;
  dispatch();
}

bool SharedLine::engaged_by_other(const LineClaimant& claimant) const {
  if (claimant.sensor_ == nullptr) return false;
  return std::any_of(engaged_.begin(), engaged_.end(), [&](const LineClaimant* engaged) {
    return engaged != &claimant && engaged->sensor_ == claimant.sensor_;
  });
}

void SharedLine::dispatch() {
  if (failure_) return;  // run() restarts first
  try {
    choose_turn();
  } catch (...) {
    fail(std::current_exception());
  }
}

void SharedLine::choose_turn() {
  if (!running_ || stopping_ || holder_ != nullptr) return;
  if (only_writes_ && waiting_.empty() && engaged_.empty()) {  // the last write is done
    stop();
    return;
  }
  const auto now = SteadyClock::now();
  claims_.clear();
  claimants_.clear();
  for (LineClaimant* claimant : waiting_) {
    if (engaged_by_other(*claimant)) continue;
    TurnClaim claim = claimant->claim_;
    claim.failing = claimant->yielded_;
    if (const GatewaySensor* sensor = claimant->sensor_) {
      claim.failing = claim.failing || failing(*sensor);
      // A late reply of its may still come until then (line_scheduling/line_claimant.h).
      claim.due = std::max(claim.due, sensor->quiet_until);
    }
    claims_.push_back(claim);
    claimants_.push_back(claimant);
  }
  const TurnChoice choice = turns_.choose(claims_, now);
  if (choice.held && on_held && claimants_[*choice.held]->sensor_ != nullptr)
    on_held(*claimants_[*choice.held]->sensor_, now);
  if (choice.turn) {
    grant(*claimants_[*choice.turn], claims_[*choice.turn].failing, choice.owed, now);
    return;
  }
  const auto wake_at = choice.next_due.value_or(SteadyClock::time_point::max());
  if (wake_.expiry() != wake_at) wake_.expires_at(wake_at);
}

void SharedLine::grant(LineClaimant& claimant, bool failing, bool owed,
                       SteadyClock::time_point now) {
  std::erase(waiting_, &claimant);
  holder_ = &claimant;
  claimant.state_ = LineClaimant::State::holding;
  claimant.outcome_ = TurnGrant::granted;
  claimant.claim_.failing = failing;
  claimant.owed_ = owed;
  claimant.turn_started_ = now;
  if (claimant.sensor_ != nullptr && !claimant.engaged_) {
    claimant.engaged_ = true;
    engaged_.push_back(&claimant);
  }
  claimant.wake_.cancel();
}

}  // namespace tiltgate
