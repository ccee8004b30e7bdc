// The short comma-separated lists of the command line, such as the simulators' sensor lists
// (`tiltgate sim FAMILY --sensors model:address,model:address`).
#pragma once

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

inline std::string_view trim_whitespace(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// The items between separators, whitespace trimmed. Empty items are kept (an empty list is one
// empty item) so that the caller can refuse them.
inline std::vector<std::string_view> split_list(std::string_view list, char separator) {
  std::vector<std::string_view> items;
  while (true) {
    const std::size_t end = list.find(separator);
    items.push_back(trim_whitespace(list.substr(0, end)));
    if (end == std::string_view::npos) return items;
    list.remove_prefix(end + 1);
  }
}

// A simulator's sensor list: `parse_item(item, index)` turns each comma-separated item into
// sensor options (an Expected with a std::string error); an empty item, or an address (the
// options' `address` member) used twice, is an error, unless `shared_addresses` allows it
// (sensors that collide, as on a bus commissioned by mistake).
template <class ParseItem>
auto parse_sensor_list(std::string_view list, ParseItem parse_item, bool shared_addresses = false)
    -> Expected<std::vector<std::decay_t<decltype(*parse_item(list, 0))>>, std::string> {
  std::vector<std::decay_t<decltype(*parse_item(list, 0))>> sensors;
  for (const std::string_view item : split_list(list, ',')) {
    if (item.empty()) return Unexpected(std::string("empty sensor in the sensor list"));
    auto sensor = parse_item(item, sensors.size());
    if (!sensor) return Unexpected(sensor.error());
    const bool taken = std::any_of(sensors.begin(), sensors.end(), [&](const auto& other) {
      return other.address == sensor->address;
    });
    if (taken && !shared_addresses) {
      return Unexpected("sensor '" + std::string(item) + "': address " +
                        std::to_string(sensor->address) + " is used twice");
    }
    sensors.push_back(std::move(*sensor));
  }
  return sensors;
}

}  // namespace tiltgate
