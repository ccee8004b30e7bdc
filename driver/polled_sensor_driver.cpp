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

boost::asio::awaitable<void> PolledSensorDriver::poll(Line& line) {
  const bool was_online = state_.online;
  const bool identity_current = identity_generation_ == line.generation();
  if (!identity_current) state_.identity_known = false;
  bool reachable = true;
  if (!identity_current) reachable = co_await read_identity(line);
  if (reachable) {
    co_await read_measurement(line);
  } else {
    ++state_.counters.polls_failed;
  }
  log_online_change(log_name(), kind(), state_.bus_address, line.name(), was_online,
                    state_.online);
}

boost::asio::awaitable<Expected<Done, LineError>> PolledSensorDriver::transact_counted(
    Line& line, LineRequest request, ExchangeOptions options) {
  request.retries = options.retries;
  request.settle = options.settle;
  ++state_.counters.transactions;
  auto sent = co_await line.transact(std::move(request));
  if (sent) {
    state_.online = true;
  } else {
    if (sent.error() == LineError::timeout) {
      ++state_.counters.timeouts;
    } else {
      ++state_.counters.io_errors;
    }
    state_.online = false;
  }
  co_return sent;
}

}  // namespace tiltgate
