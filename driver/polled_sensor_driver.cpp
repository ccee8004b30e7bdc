#include "driver/polled_sensor_driver.h"

#include <spdlog/spdlog.h>

namespace tiltgate {

namespace {

// One line when a sensor stops or starts answering, not one per poll.
void log_online_change(std::string_view sensor, std::string_view what, unsigned address,
                       std::string_view line, bool was_online, bool is_online) {
  if (was_online && !is_online) {
    spdlog::warn("{}: {} {} on {} stopped answering", sensor, what, address, line);
  } else if (!was_online && is_online) {
    spdlog::info("{}: {} {} on {} answering", sensor, what, address, line);
  }
}

}  // namespace

PolledSensorDriver::PolledSensorDriver(ReplyTimeouts timeouts) : reply_timeout_(timeouts) {
  state_.reply_timeout = reply_timeout_.current();
}

boost::asio::awaitable<void> PolledSensorDriver::poll(Line& line) {
  const bool was_online = state_.online;
  // Only after a failure: the first poll after start gets the bus's retries.
  probing_ = !state_.online && state_.counters.transactions > 0;
  const bool identity_current = identity_generation_ == line.generation();
  if (!identity_current) state_.identity_known = false;
  bool reachable = true;
  if (!identity_current) reachable = co_await read_identity(line);
  if (reachable && (settings_owed_ || !identity_current)) {
    reachable = co_await read_settings(line);
    settings_owed_ = !reachable;
  }
  if (reachable) {
    co_await read_measurement(line);
  } else {
    ++state_.counters.polls_failed;
  }
  probing_ = false;
  log_online_change(log_name(), kind(), state_.bus_address, line.name(), was_online,
                    state_.online);
}

boost::asio::awaitable<Expected<Done, LineError>> PolledSensorDriver::transact_counted(
    Line& line, LineRequest request, ExchangeOptions options) {
  int retries = options.retries >= 0 ? options.retries : line.retries();
  if (options.retries < 0 && probing_ && !state_.online) retries = 0;
  request.retries = 0;  // each attempt is a transaction of the line's, its wait adapted
  request.settle = options.settle;
  ++state_.counters.transactions;
  Expected<Done, LineError> sent = Unexpected(LineError::timeout);
  for (int attempt = 0; attempt <= retries; ++attempt) {
    request.timeout = reply_timeout_.current();
    // Named: g++ 12 destroys a temporary in co_await twice. Only a retry needs it again.
    LineRequest sending = attempt < retries ? request : std::move(request);
    sent = co_await line.transact(std::move(sending));
    note_timing(line.last_timing(), line.name());
    if (sent || sent.error() != LineError::timeout) break;
  }
  if (sent) {
    // Back from offline: it may have been changed (or replaced) while the gateway could not
    // see it, so its settings are read again.
    if (known_offline(state_)) settings_owed_ = true;
    state_.online = true;
    state_.unanswered = false;
    state_.last_answer = SteadyClock::now();
  } else if (sent.error() == LineError::expired || sent.error() == LineError::cancelled) {
    // Never sent, or cut off by a stop (the gateway's, a reload's): nothing was learnt of the
    // sensor, which must not be logged as having stopped answering.
  } else {
    if (sent.error() == LineError::timeout) {
      ++state_.counters.timeouts;
    } else {
      ++state_.counters.io_errors;
    }
    state_.online = false;
    state_.unanswered = sent.error() == LineError::timeout;
  }
  co_return sent;
}

void PolledSensorDriver::note_acknowledged(WriteTarget target, double value) {
  (void)target;
  (void)value;
  settings_owed_ = true;
}

boost::asio::awaitable<bool> PolledSensorDriver::read_settings(Line& line) {
  (void)line;
  co_return true;  // nothing the protocol can read back
}

void PolledSensorDriver::note_timing(const LineTiming& timing, const std::string& line_name) {
  state_.counters.late_replies += timing.late_replies;
  const auto before = reply_timeout_.current();
  const bool was_late = reply_timeout_.answers_late();
  reply_timeout_.record(timing);
  state_.reply_timeout = reply_timeout_.current();
  state_.answers_late = reply_timeout_.answers_late();
  if (!was_late && state_.answers_late) {
    spdlog::warn("{}: {} {} on {} answers late ({} ms after the request, time-out {} ms); its "
                 "late replies are discarded and its time-out adapted, up to {} ms",
                 log_name(), kind(), state_.bus_address, line_name,
                 timing.late_delay ? timing.late_delay->count() : 0, before.count(),
                 reply_timeout_.limits().max.count());
  } else if (was_late && !state_.answers_late) {
    spdlog::info("{}: {} {} on {} answers in time again", log_name(), kind(), state_.bus_address,
                 line_name);
  }
  if (state_.reply_timeout != before) {
    spdlog::info("{}: reply time-out {} ms (was {} ms)", log_name(),
                 state_.reply_timeout.count(), before.count());
  }
}

}  // namespace tiltgate
