#include "mqtt/mqtt_payload.h"

#include <fmt/format.h>

#include "status/status_json.h"

namespace tiltgate {

std::string mqtt_state_topic(std::string_view prefix, std::string_view sensor) {
  return fmt::format("{}/{}/state", prefix, sensor);
}

std::string mqtt_info_topic(std::string_view prefix, std::string_view sensor) {
  return fmt::format("{}/{}/info", prefix, sensor);
}

std::string mqtt_status_topic(std::string_view prefix) { return fmt::format("{}/status", prefix); }

std::string mqtt_state_json(const SensorStatus& s, std::int64_t now_unix_ms) {
  const std::int64_t ts = s.age_ms ? now_unix_ms - *s.age_ms : now_unix_ms;
  return fmt::format(
      "{{\"ts\":{},\"x\":{},\"y\":{},\"tilt\":{},\"online\":{},\"stale\":{},\"age_ms\":{},"
      "\"alarms\":{},\"wrong_device\":{}}}",
      ts, json_number(s.x), json_number(s.y), json_number(s.tilt), s.online, s.stale,
      s.age_ms ? std::to_string(*s.age_ms) : "null", s.alarms, s.wrong_device);
}

std::string mqtt_historical_state_json(std::string_view state_json) {
  if (state_json.empty() || state_json.back() != '}') return std::string(state_json);
  state_json.remove_suffix(1);
  return fmt::format("{},\"historical\":true}}", state_json);
}

std::string mqtt_info_json(const SensorStatus& s) {
  return fmt::format(
      "{{\"name\":{},\"bus\":{},\"unit_id\":{},\"address\":{},\"model\":{},\"serial\":{},"
      "\"firmware\":{},\"configured_serial\":{}}}",
      json_string(s.name), json_string(s.bus), s.unit_id, s.address, json_string(s.model),
      json_string(s.serial), json_string(s.firmware),
      s.configured_serial.empty() ? std::string("null") : json_string(s.configured_serial));
}

}  // namespace tiltgate
