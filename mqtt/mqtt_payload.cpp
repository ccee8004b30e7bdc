#include "mqtt/mqtt_payload.h"

#include <fmt/format.h>

#include "status/json_values.h"
#include "status/status_json.h"  // sensor_identity_json

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
  return json_text(Json{{"ts", ts},
                        {"x", json_number(s.x)},
                        {"y", json_number(s.y)},
                        {"tilt", json_number(s.tilt)},
                        {"online", s.online},
                        {"stale", s.stale},
                        {"age_ms", s.age_ms ? Json(*s.age_ms) : Json(nullptr)},
                        {"alarms", s.alarms},
                        {"wrong_device", s.wrong_device}});
}

std::string mqtt_historical_state_json(std::string_view state_json) {
  // Our own text, read back: anything else is passed on as it is.
  Json state = Json::parse(state_json, nullptr, false);
  if (state.is_discarded() || !state.is_object()) return std::string(state_json);
  state["historical"] = true;
  return json_text(state);
}

std::string mqtt_info_json(const SensorStatus& s) { return json_text(sensor_identity_json(s)); }

}  // namespace tiltgate
