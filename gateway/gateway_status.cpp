// Gateway::status(): the copy of the running state the HTTP status API shows.
#include <cmath>

#include "gateway/gateway.h"

namespace tiltgate {

namespace {

std::optional<double> present(double value) {
  if (std::isnan(value)) return std::nullopt;
  return value;
}

SensorStatus sensor_status(const GatewaySensor& sensor, SteadyClock::time_point now) {
  const SensorState& state = sensor.driver->state();
  SensorStatus s;
  s.name = sensor.config.name;
  s.bus = sensor.config.bus;
  s.unit_id = sensor.config.unit_id;
  s.address = state.bus_address;
  s.model = std::string(sensor.driver->model());
  s.serial = state.serial;
  s.firmware = state.firmware;
  s.online = state.online;
  s.polls_ok = state.counters.polls_ok;
  s.polls_failed = state.counters.polls_failed;
  if (state.reading) {
    const auto age = std::chrono::duration_cast<std::chrono::milliseconds>(now - state.reading->taken);
    s.age_ms = age.count();
    s.stale = age > sensor.stale_after;
    // The angles the register map serves: after mounting, once processing has seen a reading.
    const DerivedState& derived = sensor.processing.derived();
    if (derived.valid) {
      s.x = present(derived.angle_x);
      s.y = present(derived.angle_y);
      s.tilt = present(derived.tilt);
      s.alarms = derived.alarms;
    } else {
      s.x = present(state.reading->angle_x);
      s.y = present(state.reading->angle_y);
    }
  }
  return s;
}

}  // namespace

GatewayStatus Gateway::status(SteadyClock::time_point now) const {
  GatewayStatus status;
  for (const auto& sensor : sensors_) status.sensors.push_back(sensor_status(*sensor, now));
  for (std::size_t i = 0; i < buses_.size(); ++i) {
    const BusConfig& config = config_.buses[i];
    const BusSchedulerStats& stats = buses_[i].scheduler->stats();
    status.buses.push_back(BusStatus{config.name, config.port, config.baud, config.protocol,
                                     stats.polls, stats.writes, stats.forwarded});
  }
  status.modbus_clients = server_->client_count();
  status.process_start_seconds = start_seconds_;
  return status;
}

}  // namespace tiltgate
