#include "driver/polled_sensor_driver.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "driver/visible_text.h"

namespace tiltgate {

namespace {

// "answers late" is a warning once in this long per sensor; the rest are at debug.
constexpr auto kLateWarningInterval = std::chrono::minutes(10);

// One line when a sensor stops or starts answering, not one per poll. A line whose frames a
// black box keeps says so: what the wire carried before is there to be looked at.
void log_online_change(std::string_view sensor, std::string_view what, unsigned address,
                       const Line& line, bool was_online, bool is_online) {
  if (was_online && !is_online) {
    const auto kept = line.frames_kept();
    if (kept.count() > 0) {
      spdlog::warn("{}: {} {} on {} stopped answering; the line's black box holds its last {} s "
                   "(tiltgate capture --bus {} --last)",
                   sensor, what, address, line.name(), kept.count(), line.name());
    } else {
      spdlog::warn("{}: {} {} on {} stopped answering", sensor, what, address, line.name());
    }
  } else if (!was_online && is_online) {
    spdlog::info("{}: {} {} on {} answering", sensor, what, address, line.name());
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
  // A sensor silent until now may answer as another device: who it is is read again before it
  // counts as online, so that nothing reads it online with the reading from before the silence
  // or as the configured sensor before its serial was checked. The wrong one is asked each poll
  // whether the right one is back.
  if (known_offline(state_)) {
    identity_owed_ = true;
    // Back from offline: it may have been changed (or replaced) while the gateway could not
    // see it, so its settings are read again too.
    settings_owed_ = true;
  }
  rechecking_wrong_device_ = identity_current && state_.wrong_device;
  bool reachable = true;
  if (!identity_current || identity_owed_ || state_.wrong_device) {
    holding_online_ = !state_.online;
    reachable = co_await read_identity(line);
    holding_online_ = false;
    if (reachable) {
      identity_owed_ = false;
      check_serial();
      // Another device answers: online, though none of its measurements is served.
      if (state_.wrong_device) state_.online = true;
    }
  }
  rechecking_wrong_device_ = false;
  // Nothing is read of a wrong device's settings: the record stays the configured sensor's.
  if (reachable && !state_.wrong_device && (settings_owed_ || !identity_current)) {
    holding_online_ = !state_.online;
    reachable = co_await read_settings(line);
    holding_online_ = false;
    settings_owed_ = !reachable;
  }
  // A standby's line answers only what it heard the active master ask: an identity or setting
  // not asked since it listens says nothing of the sensor, whose measurement is still heard.
  if (line.listens_only()) reachable = true;
  if (reachable && !state_.wrong_device) {
    co_await read_measurement(line);
  } else {
    ++state_.counters.polls_failed;  // no measurement: none answered, or not of this sensor
  }
  probing_ = false;
  log_online_change(log_name(), kind(), state_.bus_address, line, was_online,
                    state_.online);
}

void PolledSensorDriver::check_serial() {
  // A device that does not tell its serial cannot be told apart (status bit 3 says so).
  if (!state_.identity_known || state_.serial.empty()) {
    state_.wrong_device = false;
    return;
  }
  const bool was_wrong = state_.wrong_device;
  const std::string before = std::exchange(last_serial_, state_.serial);
  const bool changed = !before.empty() && before != state_.serial;
  if (expected_serial_.empty()) {
    if (changed)
      spdlog::warn("{}: the {} at address {} now reports serial '{}', was '{}': another device? "
                   "([[sensor]] serial makes the gateway refuse one)",
                   log_name(), kind(), state_.bus_address, visible_text(state_.serial),
                   visible_text(before));
    return;
  }
  state_.wrong_device = state_.serial != expected_serial_;
  if (state_.wrong_device && (!was_wrong || changed)) {
    ++state_.counters.wrong_device_found;
    spdlog::error("{}: wrong device at address {}: serial '{}' answers, the configured sensor is "
                  "serial '{}'; its measurements read as offline and writes are refused",
                  log_name(), state_.bus_address, visible_text(state_.serial),
                  visible_text(expected_serial_));
  } else if (was_wrong && !state_.wrong_device) {
    spdlog::info("{}: serial '{}' answers at address {} again: served", log_name(),
                 visible_text(state_.serial), state_.bus_address);
  }
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
    count_attempt(sent, line.last_timing());
    if (sent || sent.error() != LineError::timeout) break;
  }
  if (sent) {
    if (!holding_online_) state_.online = true;
    state_.unanswered = false;
    state_.last_answer = SteadyClock::now();
  } else if (sent.error() == LineError::expired || sent.error() == LineError::cancelled ||
             sent.error() == LineError::overloaded) {
    // Never sent, cut off by a stop (the gateway's, a reload's), or held back by an overloaded
    // machine: nothing was learnt of the sensor, which must not be logged as having stopped
    // answering.
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

void PolledSensorDriver::count_attempt(const Expected<Done, LineError>& sent,
                                       const LineTiming& timing) {
  SensorCounters& counters = state_.counters;
  counters.bytes_out += timing.bytes_out;
  counters.bytes_in += timing.bytes_in;
  counters.overruns += timing.overruns;
  counters.uart_errors += timing.uart_errors;
  // An attempt that never reached the wire (a stop, a closed or failed port, no time left) is
  // no request; one given up as overloaded was sent.
  if (!sent && sent.error() != LineError::timeout && sent.error() != LineError::overloaded)
    return;
  ++counters.requests;
  if (sent) {
    ++counters.replies;
  } else if (sent.error() == LineError::timeout) {
    ++(timing.garbled ? counters.garbled : counters.no_reply);
  }
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
  if (timing.reply_delay) {
    const std::chrono::milliseconds took = *timing.reply_delay + timing.machine_held;
    SensorCounters& counters = state_.counters;
    counters.slowest_reply = std::max(counters.slowest_reply, took);
    const auto bound = std::lower_bound(kReplyBucketsMs.begin(), kReplyBucketsMs.end(),
                                        took.count());
    ++counters.reply_buckets[std::size_t(bound - kReplyBucketsMs.begin())];
    counters.reply_ms_sum += std::uint64_t(took.count());
  }
  const auto before = reply_timeout_.current();
  const bool was_late = reply_timeout_.answers_late();
  reply_timeout_.record(timing);
  state_.reply_timeout = reply_timeout_.current();
  state_.answers_late = reply_timeout_.answers_late();
  if (!was_late && state_.answers_late) {
    const auto now = SteadyClock::now();
    late_logged_ = !late_warned_ || now - *late_warned_ >= kLateWarningInterval;
    if (late_logged_) late_warned_ = now;
    spdlog::log(late_logged_ ? spdlog::level::warn : spdlog::level::debug,
                "{}: {} {} on {} answers late ({} ms after the request, time-out {} ms); its "
                "late replies are discarded and its time-out adapted, up to {} ms",
                log_name(), kind(), state_.bus_address, line_name,
                timing.late_delay ? timing.late_delay->count() : 0, before.count(),
                reply_timeout_.limits().max.count());
  } else if (was_late && !state_.answers_late) {
    spdlog::log(late_logged_ ? spdlog::level::info : spdlog::level::debug,
                "{}: {} {} on {} answers in time again", log_name(), kind(), state_.bus_address,
                line_name);
  }
  // Every few seconds under load: the status API and the registers show the time-out in use.
  if (state_.reply_timeout != before) {
    spdlog::debug("{}: reply time-out {} ms (was {} ms)", log_name(),
                  state_.reply_timeout.count(), before.count());
  }
}

}  // namespace tiltgate
