#include "gateway/status_copy.h"

#include <algorithm>
#include <cmath>

namespace tiltgate {

namespace {

std::optional<double> present(double value) {
  if (std::isnan(value)) return std::nullopt;
  return value;
}

// Adds one listener's request or exception counts to the totals, keeping them in key order.
template <class Count>
void add_counts(std::vector<Count>& totals, const std::vector<Count>& counts) {
  const auto key = [](const Count& c) {
    if constexpr (requires { c.exception; }) return std::pair(c.function, c.exception);
    else return std::pair(c.function, std::uint8_t(0));
  };
  for (const Count& count : counts) {
    auto at = std::find_if(totals.begin(), totals.end(),
                           [&](const Count& total) { return key(total) == key(count); });
    if (at != totals.end())
      at->count += count.count;
    else
      totals.push_back(count);
  }
  std::sort(totals.begin(), totals.end(),
            [&](const Count& a, const Count& b) { return key(a) < key(b); });
}

}  // namespace

// Rates are estimates over a few seconds: more digits than these would only be noise.
// Division by the scale (not multiplication by a step) gives the double nearest the decimal.
std::optional<double> rounded(std::optional<double> value, double scale) {
  if (!value) return std::nullopt;
  return std::round(*value * scale) / scale;
}

FailureCounts failure_counts(const SensorCounters& counters) {
  return FailureCounts{counters.polls_failed, counters.timeouts, counters.checksum_errors,
                       counters.io_errors, counters.late_replies};
}

ExchangeCounts exchange_counts(const SensorCounters& c) {
  return ExchangeCounts{c.requests, c.replies,  c.garbled,  c.no_reply,
                        c.refused,  c.busy,     c.bytes_out, c.bytes_in,
                        c.overruns, c.uart_errors};
}

SensorStatus sensor_status(const GatewaySensor& sensor, SteadyClock::time_point now) {
  const SensorState& state = sensor.driver->state();
  SensorStatus s;
  s.name = sensor.config.name;
  s.bus = sensor.config.bus;
  s.unit_id = sensor.config.unit_id;
  s.address = state.bus_address;
  // The device's own word for its model where it gives one, else what its driver runs it as.
  s.model = state.model.empty() ? std::string(sensor.driver->model()) : state.model;
  s.serial = state.serial;
  s.configured_serial = sensor.config.serial;
  s.wrong_device = state.wrong_device;
  s.wrong_device_found = state.counters.wrong_device_found;
  s.firmware = state.firmware;
  s.online = online_at(state, now, sensor.stale_after);
  s.polls_ok = state.counters.polls_ok;
  s.polls_failed = state.counters.polls_failed;
  s.timeouts = state.counters.timeouts;
  s.checksum_errors = state.counters.checksum_errors;
  s.io_errors = state.counters.io_errors;
  s.late_replies = state.counters.late_replies;
  s.exchanges = exchange_counts(state.counters);
  s.slowest_reply_ms = state.counters.slowest_reply.count();
  s.reply_buckets = state.counters.reply_buckets;
  s.reply_ms_sum = state.counters.reply_ms_sum;
  s.line_seconds = std::chrono::duration<double>(sensor.line_time).count();
  if (sensor.model != nullptr)
    for (const SettingDescriptor& setting : sensor.model->settings)
      if (setting.id != WriteTarget::command)  // a one-shot command, no value to keep
        s.settings.emplace_back(std::string(setting.name), state.settings.get(setting.id));
  for (std::size_t code = 0; code < state.counters.refusals.size(); ++code)
    if (state.counters.refusals[code] > 0)
      s.refusals.emplace_back(std::uint8_t(code), state.counters.refusals[code]);
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
      s.alarms_danger = derived.alarms_danger;
      s.alarms_latched = derived.alarms_latched;
      s.relative_x = present(derived.relative_x);
      s.relative_y = present(derived.relative_y);
      s.displacement_x_mm = present(derived.displacement_x_mm);
      s.displacement_y_mm = present(derived.displacement_y_mm);
      s.displacement_mm = present(derived.displacement_mm);
      if (derived.taken_unix_ms != 0) s.reading_unix_ms = derived.taken_unix_ms;
      s.clock_synchronised = derived.clock_synchronised;
    } else {
      s.x = present(state.reading->angle_x);
      s.y = present(state.reading->angle_y);
    }
    s.temperature = present(state.reading->temperature_c.value_or(NAN));
  }
  return s;
}

BusStatus bus_status(const BusConfig& config, const BusSchedulerStats& stats, const LineStats& line,
                     std::optional<double> polls_per_s, std::optional<double> busy_share) {
  BusStatus bus;
  bus.name = config.name;
  bus.port = config.port;
  bus.baud = config.baud;
  bus.protocol = config.protocol;
  bus.polls = stats.polls;
  bus.writes = stats.writes;
  bus.forwarded = stats.forwarded;
  bus.restarts = stats.restarts;
  bus.machine_held = line.machine_held;
  bus.overloaded = line.overloaded;
  bus.bytes_out = line.bytes_out;
  bus.bytes_in = line.bytes_in;
  bus.stray_bytes = line.stray_bytes;
  bus.reopens = line.reopens;
  bus.busy_seconds = std::chrono::duration<double>(stats.busy).count();
  bus.polls_per_s = rounded(polls_per_s, 100);
  // A turn that ran across the sample instant counts wholly in the later sample, so a busy
  // share can come out a little over 1 for a moment.
  if (const auto busy = rounded(busy_share, 1000)) bus.utilisation = std::min(*busy, 1.0);
  return bus;
}

void add_sensor_failures(BusStatus& bus, const std::vector<SensorStatus>& sensors) {
  FailureCounts recent;
  bool counted = true;
  for (const SensorStatus& s : sensors) {
    if (s.bus != bus.name) continue;
    bus.failures += failure_counts(s);
    bus.exchanges += s.exchanges;
    if (s.recent_failures)
      recent += *s.recent_failures;
    else
      counted = false;
  }
  if (counted) bus.recent_failures = recent;
}

void add_listener_counts(GatewayStatus& status, const ModbusTcpServer& listener) {
  const ModbusServerStats server = listener.stats();
  status.modbus_clients += listener.client_count();
  status.modbus_connections += server.accepted;
  status.modbus_connections_refused += server.refused;
  status.modbus_connections_replaced += server.replaced;
  status.modbus_connections_denied += server.denied;
  status.modbus_writes_denied += server.writes_denied;
  status.modbus_tls_refused += server.tls_refused;
  status.modbus_requests_delayed += server.requests_delayed;
  status.modbus_request_delay_seconds += double(server.delay_ns) / 1e9;
  add_counts(status.modbus_requests, listener.request_counts().requests());
  add_counts(status.modbus_exceptions, listener.request_counts().exceptions());
}

}  // namespace tiltgate
