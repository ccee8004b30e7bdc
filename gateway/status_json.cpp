#include "gateway/status_json.h"

#include <fmt/format.h>

#include <cmath>

namespace tiltgate {

std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
        else
          out += c;
    }
  }
  return out + "\"";
}

std::string json_number(std::optional<double> value) {
  if (!value || !std::isfinite(*value)) return "null";
  // fmt's shortest form that reads back the same double, e.g. 1.5, -0.25, 1e-05.
  return fmt::format("{}", *value);
}

namespace {

std::string json_integer(std::optional<std::int64_t> value) {
  return value ? std::to_string(*value) : "null";
}

template <class Item, class Write>
std::string json_array(const std::vector<Item>& items, Write write) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += ",";
    out += write(items[i]);
  }
  return out + "]";
}

}  // namespace

std::string sensor_json(const SensorStatus& s) {
  return fmt::format(
      "{{\"name\":{},\"bus\":{},\"unit_id\":{},\"address\":{},\"model\":{},\"serial\":{},"
      "\"firmware\":{},\"online\":{},\"stale\":{},\"x\":{},\"y\":{},\"tilt\":{},\"age_ms\":{},"
      "\"alarms\":{},\"polls_ok\":{},\"polls_failed\":{}}}",
      json_string(s.name), json_string(s.bus), s.unit_id, s.address, json_string(s.model),
      json_string(s.serial), json_string(s.firmware), s.online, s.stale, json_number(s.x),
      json_number(s.y), json_number(s.tilt), json_integer(s.age_ms), s.alarms, s.polls_ok,
      s.polls_failed);
}

std::string sensors_json(const std::vector<SensorStatus>& sensors) {
  return json_array(sensors, sensor_json);
}

std::string buses_json(const std::vector<BusStatus>& buses) {
  return json_array(buses, [](const BusStatus& b) {
    return fmt::format(
        "{{\"name\":{},\"port\":{},\"baud\":{},\"protocol\":{},\"polls\":{},\"writes\":{},"
        "\"forwarded\":{}}}",
        json_string(b.name), json_string(b.port), b.baud, json_string(b.protocol), b.polls,
        b.writes, b.forwarded);
  });
}

}  // namespace tiltgate
