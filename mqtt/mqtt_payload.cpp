#include "mqtt/mqtt_payload.h"

#include <fmt/format.h>

#include "status/json_values.h"
#include "status/status_json.h"  // sensor_identity_json

namespace tiltgate {

std::string mqtt_state_topic(std::string_view prefix, std::string_view sensor) {
  return fmt::format("{}/{}/state", prefix, sensor);
}

std::string mqtt_events_topic(std::string_view prefix) { return fmt::format("{}/events", prefix); }

std::string mqtt_burst_topic(std::string_view prefix, std::string_view sensor) {
  return fmt::format("{}/{}/burst", prefix, sensor);
}

std::string mqtt_info_topic(std::string_view prefix, std::string_view sensor) {
  return fmt::format("{}/{}/info", prefix, sensor);
}

std::string mqtt_status_topic(std::string_view prefix) { return fmt::format("{}/status", prefix); }

std::string mqtt_state_json(const SensorStatus& s, const ClockState& clock,
                            std::int64_t now_unix_ms) {
  // The reading's own UTC stamp (when its reply arrived), else now less its age.
  const std::int64_t ts = s.reading_unix_ms ? *s.reading_unix_ms
                          : s.age_ms        ? now_unix_ms - *s.age_ms
                                            : now_unix_ms;
  return json_text(Json{{"ts", ts},
                        {"x", json_number(s.x)},
                        {"y", json_number(s.y)},
                        {"tilt", json_number(s.tilt)},
                        {"relative_x", json_number(s.relative_x)},
                        {"relative_y", json_number(s.relative_y)},
                        {"displacement_mm", json_number(s.displacement_mm)},
                        {"temperature", json_number(s.temperature)},
                        {"online", s.online},
                        {"stale", s.stale},
                        {"age_ms", s.age_ms ? Json(*s.age_ms) : Json(nullptr)},
                        {"alarms", s.alarms},
                        {"alarms_danger", s.alarms_danger},
                        {"alarms_latched", s.alarms_latched},
                        {"wrong_device", s.wrong_device},
                        {"reading_clock_synchronised", s.clock_synchronised},
                        {"clock_synchronised", clock.synchronised},
                        {"clock_error_ms", json_number(clock.error_ms)}});
}

std::string mqtt_historical_state_json(std::string_view state_json) {
  // Our own text, read back: anything else is passed on as it is.
  Json state = Json::parse(state_json, nullptr, false);
  if (state.is_discarded() || !state.is_object()) return std::string(state_json);
  state["historical"] = true;
  return json_text(state);
}

std::string mqtt_burst_json(const monitoring::BurstBatch& batch) {
  Json samples = Json::array();
  for (const FedSample& s : batch.samples)
    samples.push_back(Json{{"ts", s.unix_ms},
                           {"x", json_number(s.x)},
                           {"y", json_number(s.y)},
                           {"tilt", json_number(s.tilt)},
                           {"relative_x", json_number(s.relative_x)},
                           {"relative_y", json_number(s.relative_y)},
                           {"displacement_mm", json_number(s.displacement_mm)},
                           {"temperature", json_number(s.temperature_c)},
                           {"alarms", s.alarms},
                           {"clock_synchronised", s.clock_synchronised}});
  return json_text(Json{{"sensor", batch.sensor},
                        {"burst", batch.id},
                        {"phase", batch.phase},
                        {"historical", true},
                        {"samples", std::move(samples)}});
}

std::string mqtt_info_json(const SensorStatus& s) { return json_text(sensor_identity_json(s)); }

}  // namespace tiltgate
