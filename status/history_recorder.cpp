#include "status/history_recorder.h"

#include <algorithm>

namespace tiltgate {

namespace {

// An angle or the temperature of a fresh reading.
std::optional<float> angle(const SensorStatus& sensor, const std::optional<double>& value) {
  if (sensor.stale || !value) return std::nullopt;
  return float(*value);
}

}  // namespace

HistoryRecorder::HistoryRecorder(std::vector<std::string> sensor_names,
                                 std::size_t samples_per_sensor,
                                 const std::vector<std::string>& with_temperature)
    : names_(std::move(sensor_names)) {
  rings_.reserve(names_.size());
  for (const std::string& name : names_)
    rings_.emplace_back(samples_per_sensor,
                        std::find(with_temperature.begin(), with_temperature.end(), name) !=
                            with_temperature.end());
}

void HistoryRecorder::record(const GatewayStatus& status, std::int64_t unix_ms) {
  // Snapshots list the sensors in configuration order, as names_ does: match by position,
  // and by name only when that fails.
  for (std::size_t i = 0; i < status.sensors.size(); ++i) {
    const SensorStatus& sensor = status.sensors[i];
    std::size_t ring = i;
    if (ring >= names_.size() || names_[ring] != sensor.name) {
      ring = 0;
      while (ring < names_.size() && names_[ring] != sensor.name) ++ring;
      if (ring == names_.size()) continue;
    }
    rings_[ring].push(AngleSample{unix_ms, angle(sensor, sensor.x), angle(sensor, sensor.y),
                                  angle(sensor, sensor.temperature)});
  }
}

void HistoryRecorder::carry_over(const HistoryRecorder& previous) {
  for (std::size_t i = 0; i < names_.size(); ++i)
    for (std::size_t j = 0; j < previous.names_.size(); ++j)
      if (previous.names_[j] == names_[i] &&
          previous.rings_[j].capacity() == rings_[i].capacity() &&
          previous.rings_[j].keeps_temperatures() == rings_[i].keeps_temperatures())
        rings_[i] = previous.rings_[j];
}

std::optional<std::vector<AngleSample>> HistoryRecorder::history(std::string_view sensor) const {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == sensor) return rings_[i].samples();
  return std::nullopt;
}

}  // namespace tiltgate
