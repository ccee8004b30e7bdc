// What the HTTP status API and the metrics show of a running gateway: a copy of each sensor's
// and each bus's state taken at one moment, as plain values, so the text built from it
// (gateway/status_json.h, gateway/status_metrics.h) is pure and testable without a bus.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tiltgate {

struct SensorStatus {
  std::string name;
  std::string bus;
  int unit_id = 0;
  std::uint32_t address = 0;    // on its bus, as polled now
  std::string model;
  std::string serial;           // empty until the sensor has reported it
  std::string firmware;
  bool online = false;          // the last exchange with the sensor got a valid reply
  bool stale = true;            // no reading, or the last is older than its stale_ms
  // Degrees after mounting, as the register map serves them; none before the first reading,
  // y none on single-axis sensors.
  std::optional<double> x;
  std::optional<double> y;
  std::optional<double> tilt;
  std::optional<std::int64_t> age_ms;  // since the last reading arrived; none without one
  std::uint16_t alarms = 0;            // mapping/derived_state.h alarm_bit flags
  std::uint64_t polls_ok = 0;
  std::uint64_t polls_failed = 0;
};

struct BusStatus {
  std::string name;
  std::string port;
  std::uint32_t baud = 0;
  std::string protocol;
  std::uint64_t polls = 0;
  std::uint64_t writes = 0;
  std::uint64_t forwarded = 0;
};

struct GatewayStatus {
  std::vector<SensorStatus> sensors;
  std::vector<BusStatus> buses;
  std::size_t modbus_clients = 0;      // Modbus TCP connections open now
  double process_start_seconds = 0;    // Unix time the gateway started, in seconds
};

}  // namespace tiltgate
