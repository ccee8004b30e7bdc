#include "spectron/sensor_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "driver/text_list.h"
#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {
namespace {

bool is_dyna(std::string_view model) {
  constexpr std::string_view kModel = "dyna";
  return std::equal(model.begin(), model.end(), kModel.begin(), kModel.end(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) == b;
  });
}

Expected<SimulatedDynaOptions, std::string> parse_item(std::string_view item, std::size_t index,
                                                       Protocol protocol) {
  const std::size_t colon = item.find(':');
  if (!is_dyna(trim_whitespace(item.substr(0, colon)))) {
    return Unexpected("sensor '" + std::string(item) + "': model must be dyna");
  }
  const int min = eeprom::min_address(protocol);
  const int max = eeprom::max_address(protocol);
  int address = min;
  if (colon != std::string_view::npos) {
    const std::string_view text = trim_whitespace(item.substr(colon + 1));
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

Expected<std::vector<SimulatedDynaOptions>, std::string> parse_sensor_spec(
    std::string_view spec, Protocol protocol, bool shared_addresses) {
  return parse_sensor_list(
      spec,
      [protocol](std::string_view item, std::size_t index) {
        return parse_item(item, index, protocol);
      },
      shared_addresses);
}

}  // namespace tiltgate::spectron
