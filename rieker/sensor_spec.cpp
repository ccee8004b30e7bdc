#include "rieker/sensor_spec.h"

#include <cctype>
#include <charconv>
#include <cstdio>

#include "driver/text_list.h"

namespace tiltgate::rieker {
namespace {

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

Expected<SimulatedSensorOptions, std::string> parse_item(std::string_view item, std::size_t index) {
  const std::size_t colon = item.find(':');
  const std::string model_text = lowercase(trim_whitespace(item.substr(0, colon)));
  const auto model = model_from_name(model_text);
  if (!model) {
    return Unexpected("sensor '" + std::string(item) + "': model must be h6 or h4360");
  }
  SimulatedSensorOptions sensor;
  sensor.model = *model;
  if (colon != std::string_view::npos) {
    const std::string_view text = trim_whitespace(item.substr(colon + 1));
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

Expected<std::vector<SimulatedSensorOptions>, std::string> parse_sensor_spec(
    std::string_view spec, bool shared_addresses) {
  return parse_sensor_list(spec, parse_item, shared_addresses);
}

}  // namespace tiltgate::rieker
