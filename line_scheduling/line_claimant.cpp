#include "line_scheduling/line_claimant.h"

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>

#include "line_scheduling/shared_line.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// One transaction's timing over its attempts: the reply's delay from the attempt that got it,
// every late burst, the latest of them.
void add_attempt(LineTiming& total, const LineTiming& attempt) {
  total.reply_delay = attempt.reply_delay;
  total.garbled = attempt.garbled;
  total.late_replies += attempt.late_replies;
  total.bytes_out += attempt.bytes_out;
  total.bytes_in += attempt.bytes_in;
  total.overruns += attempt.overruns;
  total.uart_errors += attempt.uart_errors;
  total.machine_held += attempt.machine_held;
  if (attempt.late_delay)
    total.late_delay = std::max(total.late_delay.value_or(attempt.late_delay.value()),
                                *attempt.late_delay);
}

}  // namespace

LineClaimant::LineClaimant(SharedLine& line, TurnKind kind, GatewaySensor* sensor,
                           std::optional<SteadyClock::time_point> deadline, std::uint64_t client)
    : shared_(&line), line_(line.line()), sensor_(sensor), deadline_(deadline),
      wake_(line.executor()) {
  claim_.kind = kind;
  claim_.client = client;
}

LineClaimant::~LineClaimant() { finish(); }

asio::awaitable<TurnGrant> LineClaimant::wait_turn(std::optional<SteadyClock::time_point> due) {
  claim_.due = due.value_or(SteadyClock::now());
  claim_.retry = RetryAfter::nothing;
  yielded_ = false;
  yield_next_ = false;
  std::optional<SteadyClock::time_point> expiry;
  if (deadline_) {
    // Its first attempt must be able to end before the deadline.
    const auto wait =
        sensor_ != nullptr ? sensor_->driver->state().reply_timeout : std::chrono::milliseconds(0);
    expiry = *deadline_ - line_.longest_attempt(wait, 0);
  }
  co_return co_await this->wait(expiry);
}

asio::awaitable<TurnGrant> LineClaimant::wait_again(const LineRequest& request) {
  // Holding it, unless an earlier wait of this work ended without a turn (expired).
  if (state_ == State::holding) shared_->end_turn(*this);
  yielded_ = true;
  claim_.due = SteadyClock::now();
  std::optional<SteadyClock::time_point> expiry;
  if (deadline_) expiry = *deadline_ - line_.longest_attempt(request.timeout, request.bytes.size());
  co_return co_await wait(expiry);
}

asio::awaitable<TurnGrant> LineClaimant::wait(std::optional<SteadyClock::time_point> expiry) {
  if (shared_ == nullptr) co_return TurnGrant::refused;
  outcome_.reset();
  state_ = State::waiting;
  shared_->enqueue(*this);  // granted or refused at once, it may be
  wake_.expires_at(expiry.value_or(SteadyClock::time_point::max()));
  while (!outcome_) {
    boost::system::error_code ec;
    co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (outcome_ || ec == asio::error::operation_aborted) continue;
    // The expiry passed while it waited.
    if (shared_ != nullptr) shared_->withdraw(*this);
    state_ = State::idle;
    outcome_ = TurnGrant::expired;
  }
  co_return *outcome_;
}

void LineClaimant::finish() {
  if (shared_ == nullptr) return;
  if (engaged_) shared_->disengage(*this);
  if (state_ == State::waiting) shared_->withdraw(*this);
  if (state_ == State::holding) shared_->end_turn(*this);
  state_ = State::idle;
}

bool LineClaimant::attempt_fits(const LineRequest& request) const {
  return !deadline_ || SteadyClock::now() + line_.longest_attempt(request.timeout,
                                                                  request.bytes.size()) <=
                           *deadline_;
}

asio::awaitable<Expected<Done, LineError>> LineClaimant::transact(LineRequest request) {
  timing_ = LineTiming{};
  const int retries = request.retries < 0 ? line_.retries() : request.retries;
  request.retries = 0;
  Expected<Done, LineError> sent = Unexpected(LineError::cancelled);
  for (int attempt = 0; attempt <= retries; ++attempt) {
    if (shared_ == nullptr) co_return Unexpected(LineError::cancelled);
    if (yield_next_) {
      const TurnGrant grant = co_await wait_again(request);
      if (grant == TurnGrant::refused) co_return Unexpected(LineError::cancelled);
      if (grant == TurnGrant::expired) co_return Unexpected(LineError::expired);
    }
    if (!attempt_fits(request)) co_return Unexpected(LineError::expired);
    // A round's owed poll gives the line up early if its sensor fell silent (line_turns.h).
    request.release_when_silent = owed_ && !claim_.failing;
    // Named: g++ 12 destroys a temporary in co_await twice. Only a retry needs it again.
    LineRequest sending = attempt < retries ? request : std::move(request);
    sent = co_await line_.transact(std::move(sending));
    const LineTiming& attempt_timing = line_.last_timing();
    add_attempt(timing_, attempt_timing);
    const bool timed_out = !sent && sent.error() == LineError::timeout;
    if (timed_out) {
      // A turn with a time-out (and its late-reply guard) was a failing one: the round's polls
      // go before the next such turn.
      claim_.failing = true;
      claim_.retry = attempt_timing.garbled ? RetryAfter::garble : RetryAfter::silence;
      // Given up before its late window closed: nothing goes to its device before then.
      if (attempt_timing.late_window_end && sensor_ != nullptr)
        sensor_->quiet_until = std::max(sensor_->quiet_until, *attempt_timing.late_window_end);
    } else {
      claim_.retry = RetryAfter::nothing;  // answered: a turn after this one is no retry
    }
    // A failing claim's every attempt is a turn of its own.
    yield_next_ = claim_.failing;
    if (!timed_out) break;
  }
  co_return sent;
}

std::uint64_t LineClaimant::generation() const { return line_.generation(); }
bool LineClaimant::is_open() const { return line_.is_open(); }
int LineClaimant::retries() const { return line_.retries(); }
const std::string& LineClaimant::name() const { return line_.name(); }
const LineStats& LineClaimant::stats() const { return line_.stats(); }

std::chrono::seconds LineClaimant::frames_kept() const { return line_.frames_kept(); }

std::chrono::milliseconds LineClaimant::longest_attempt(std::chrono::milliseconds timeout,
                                                        std::size_t request_bytes) const {
  return line_.longest_attempt(timeout, request_bytes);
}

}  // namespace tiltgate
