#include "rieker/sensor_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>

namespace tiltgate::rieker {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

Expected<SimulatedSensorOptions, std::string> parse_item(std::string_view item, std::size_t index) {
  const std::size_t colon = item.find(':');
  const std::string model_text = lowercase(trim(item.substr(0, colon)));
  const auto model = model_from_name(model_text);
  if (!model) {
    return Unexpected("sensor '" + std::string(item) + "': model must be h6 or h4360");
  }
  SimulatedSensorOptions sensor;
  sensor.model = *model;
  if (colon != std::string_view::npos) {
    const std::string_view text = trim(item.substr(colon + 1));
    unsigned address = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), address);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty() ||
        address < kMinSensorAddress || address > kMaxSensorAddress) {
      return Unexpected("sensor '" + std::string(item) + "': address must be 1..65000");
    }
    sensor.address = static_cast<std::uint16_t>(address);
  }
  char serial[16];
  std::snprintf(serial, sizeof serial, "96%05u", static_cast<unsigned>(sensor.address));
  sensor.serial = serial;
  sensor.angle_x = 1.0 + static_cast<double>(index);
  sensor.angle_y = -sensor.angle_x;
  sensor.sway_amplitude = 0.25;
  sensor.sway_period_s = 30.0;
  return sensor;
}

}  // namespace

Expected<std::vector<SimulatedSensorOptions>, std::string> parse_sensor_spec(std::string_view spec) {
  std::vector<SimulatedSensorOptions> sensors;
  while (true) {
    const std::size_t comma = spec.find(',');
    const std::string_view item = trim(spec.substr(0, comma));
    if (item.empty()) return Unexpected(std::string("empty sensor in the sensor list"));
    auto sensor = parse_item(item, sensors.size());
    if (!sensor) return Unexpected(sensor.error());
    const bool taken = std::any_of(sensors.begin(), sensors.end(), [&](const auto& other) {
      return other.address == sensor->address;
    });
    if (taken) {
      return Unexpected("sensor '" + std::string(item) + "': address " +
                        std::to_string(sensor->address) + " is used twice");
    }
    sensors.push_back(std::move(*sensor));
    if (comma == std::string_view::npos) break;
    spec.remove_prefix(comma + 1);
  }
  return sensors;
}

}  // namespace tiltgate::rieker
