#include "status/status_json.h"

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

// {"3":2,"5":1}: refusals by their protocol's code.
std::string naks_json(const std::vector<std::pair<std::uint8_t, std::uint64_t>>& refusals) {
  std::string out = "{";
  for (std::size_t i = 0; i < refusals.size(); ++i) {
    if (i > 0) out += ",";
    out += fmt::format("\"{}\":{}", refusals[i].first, refusals[i].second);
  }
  return out + "}";
}

// {"filter":2,"zero_x":null}: the settings record, null where unknown.
std::string settings_json(const std::vector<std::pair<std::string, std::optional<double>>>& settings) {
  std::string out = "{";
  for (std::size_t i = 0; i < settings.size(); ++i) {
    if (i > 0) out += ",";
    out += fmt::format("{}:{}", json_string(settings[i].first), json_number(settings[i].second));
  }
  return out + "}";
}

}  // namespace

std::string sensor_json(const SensorStatus& s) {
  return fmt::format(
      "{{\"name\":{},\"bus\":{},\"unit_id\":{},\"address\":{},\"model\":{},\"serial\":{},"
      "\"firmware\":{},\"configured_serial\":{},\"wrong_device\":{},\"online\":{},"
      "\"stale\":{},\"x\":{},\"y\":{},\"tilt\":{},\"age_ms\":{},"
      "\"alarms\":{},\"polls_ok\":{},\"polls_failed\":{},\"polls_per_s\":{},"
      "\"failures\":{{\"timeout\":{},\"checksum\":{},\"io_error\":{},\"late_reply\":{}}},"
      "\"naks\":{},\"line_seconds\":{},\"line_share\":{},\"settings\":{}}}",
      json_string(s.name), json_string(s.bus), s.unit_id, s.address, json_string(s.model),
      json_string(s.serial), json_string(s.firmware),
      s.configured_serial.empty() ? std::string("null") : json_string(s.configured_serial),
      s.wrong_device, s.online, s.stale, json_number(s.x),
      json_number(s.y), json_number(s.tilt), json_integer(s.age_ms), s.alarms, s.polls_ok,
      s.polls_failed, json_number(s.polls_per_s), s.timeouts, s.checksum_errors, s.io_errors,
      s.late_replies, naks_json(s.refusals), json_number(s.line_seconds),
      json_number(s.line_share), settings_json(s.settings));
}

std::string sensors_json(const std::vector<SensorStatus>& sensors) {
  return json_array(sensors, sensor_json);
}

std::string modbus_json(const GatewayStatus& s) {
  return fmt::format(
      "{{\"clients\":{},\"connections\":{},\"refused\":{},\"replaced\":{},\"denied\":{},"
      "\"writes_denied\":{},\"tls_refused\":{},\"http_denied\":{}}}",
      s.modbus_clients, s.modbus_connections, s.modbus_connections_refused,
      s.modbus_connections_replaced, s.modbus_connections_denied, s.modbus_writes_denied,
      s.modbus_tls_refused, s.http_connections_denied);
}

std::string buses_json(const std::vector<BusStatus>& buses) {
  return json_array(buses, [](const BusStatus& b) {
    return fmt::format(
        "{{\"name\":{},\"port\":{},\"baud\":{},\"protocol\":{},\"polls\":{},\"writes\":{},"
        "\"forwarded\":{},\"busy_seconds\":{},\"polls_per_s\":{},\"utilisation\":{}}}",
        json_string(b.name), json_string(b.port), b.baud, json_string(b.protocol), b.polls,
        b.writes, b.forwarded, json_number(b.busy_seconds), json_number(b.polls_per_s),
        json_number(b.utilisation));
  });
}

}  // namespace tiltgate
