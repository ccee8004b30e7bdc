#include "monitoring/event_record.h"

#include "monitoring/utc_time.h"
#include "status/json_values.h"

namespace tiltgate::monitoring {

namespace {

void put_text(Json& object, const char* key, const std::string& text) {
  if (!text.empty()) object[key] = text;
}

std::optional<double> number_at(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

std::string text_at(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
}

}  // namespace

std::string event_json(const EventRecord& e) {
  Json object = {{"seq", e.seq}, {"time", utc_timestamp(e.unix_ms)}, {"unix_ms", e.unix_ms},
                 {"sensor", e.sensor}, {"kind", e.kind}};
  put_text(object, "alarm", e.alarm);
  put_text(object, "level", e.level);
  put_text(object, "state", e.state);
  if (e.kind == "alarm") {
    object["value"] = json_number(e.value);
    object["threshold"] = json_number(e.threshold);
  }
  if (e.kind == "baseline") {
    object["value"] = {{"x", json_number(e.x)}, {"y", json_number(e.y)}};
    object["previous"] = {{"x", json_number(e.previous_x)}, {"y", json_number(e.previous_y)}};
  }
  put_text(object, "by", e.by);
  put_text(object, "text", e.text);
  return json_text(object);
}

std::optional<EventRecord> event_from_json(std::string_view text) {
  const nlohmann::json object = nlohmann::json::parse(text, nullptr, false);
  if (!object.is_object()) return std::nullopt;
  const auto seq = object.find("seq");
  const auto unix_ms = object.find("unix_ms");
  if (seq == object.end() || !seq->is_number_unsigned() || unix_ms == object.end() ||
      !unix_ms->is_number_integer())
    return std::nullopt;
  EventRecord e;
  e.seq = seq->get<std::uint64_t>();
  e.unix_ms = unix_ms->get<std::int64_t>();
  e.sensor = text_at(object, "sensor");
  e.kind = text_at(object, "kind");
  e.alarm = text_at(object, "alarm");
  e.level = text_at(object, "level");
  e.state = text_at(object, "state");
  e.by = text_at(object, "by");
  e.text = text_at(object, "text");
  if (e.kind == "alarm") {
    e.value = number_at(object, "value");
    e.threshold = number_at(object, "threshold");
  }
  if (e.kind == "baseline") {
    if (const auto it = object.find("value"); it != object.end() && it->is_object()) {
      e.x = number_at(*it, "x");
      e.y = number_at(*it, "y");
    }
    if (const auto it = object.find("previous"); it != object.end() && it->is_object()) {
      e.previous_x = number_at(*it, "x");
      e.previous_y = number_at(*it, "y");
    }
  }
  return e;
}

}  // namespace tiltgate::monitoring
