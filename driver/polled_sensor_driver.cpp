#include "driver/polled_sensor_driver.h"

#include "driver/online_log.h"

namespace tiltgate {

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

}  // namespace tiltgate
