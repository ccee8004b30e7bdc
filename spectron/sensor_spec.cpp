#include "spectron/sensor_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

bool is_dyna(std::string_view model) {
  constexpr std::string_view kModel = "dyna";
  return std::equal(model.begin(), model.end(), kModel.begin(), kModel.end(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) == b;
  });
}

Expected<SimulatedDynaOptions, std::string> parse_item(std::string_view item, std::size_t index,
                                                       Protocol protocol) {
  const std::size_t colon = item.find(':');
  if (!is_dyna(trim(item.substr(0, colon)))) {
    return Unexpected("sensor '" + std::string(item) + "': model must be dyna");
  }
  const int min = eeprom::min_address(protocol);
  const int max = eeprom::max_address(protocol);
  int address = min;
  if (colon != std::string_view::npos) {
    const std::string_view text = trim(item.substr(colon + 1));
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), address);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || address < min ||
        address > max) {
      return Unexpected("sensor '" + std::string(item) + "': address must be " +
                        std::to_string(min) + ".." + std::to_string(max) + " on a " +
                        protocol_name(protocol) + " bus");
    }
  }
  SimulatedDynaOptions sensor;
  sensor.address = static_cast<std::uint8_t>(address);
  sensor.serial = static_cast<std::uint16_t>(10000 + address);
  // Capped so that a long list stays within a signed 16-bit reading.
  sensor.counts = static_cast<std::int16_t>(1000 * std::min<std::size_t>(index + 1, 30));
  sensor.sway_amplitude = 50.0;
  sensor.sway_period_s = 30.0;
  sensor.temperature = static_cast<std::int16_t>(250 + 10 * std::min<std::size_t>(index, 1000));
  return sensor;
}

}  // namespace

Expected<std::vector<SimulatedDynaOptions>, std::string> parse_sensor_spec(std::string_view spec,
                                                                         Protocol protocol) {
  std::vector<SimulatedDynaOptions> sensors;
  while (true) {
    const std::size_t comma = spec.find(',');
    const std::string_view item = trim(spec.substr(0, comma));
    if (item.empty()) return Unexpected(std::string("empty sensor in the sensor list"));
    auto sensor = parse_item(item, sensors.size(), protocol);
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

}  // namespace tiltgate::spectron
