// How the gateway writes its JSON (the status API, the angle history, the MQTT payloads):
// through nlohmann's ordered_json, so keys keep the order they are written in (the API's
// documented order, and what the tests compare), with numbers as the status page and
// subscribers expect them. Header-only, like nlohmann itself: the MQTT feed uses it without
// linking the HTTP server.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace tiltgate {

using Json = nlohmann::ordered_json;

// A number, or null for none, NaN and the infinities (JSON has none of them). A whole number
// is written as one (2, not nlohmann's 2.0: a filter setting, a count of seconds); any other as
// the shortest text that reads back the same double (12.345, 0.031, 1e-05).
inline Json json_number(std::optional<double> value) {
  if (!value || !std::isfinite(*value)) return nullptr;
  // Within 2^53 every whole double is exactly an integer.
  constexpr double kExactWhole = 9007199254740992.0;
  if (std::trunc(*value) == *value && std::fabs(*value) < kExactWhole)
    return std::int64_t(*value);
  return *value;
}

// A float (the angle history keeps float samples) as the shortest text that reads back the
// same float: -12.345, not the -12.345000267028809 its widening to double would print.
inline Json json_float_number(std::optional<float> value) {
  if (!value || !std::isfinite(*value)) return nullptr;
  char text[32];
  const auto written = std::to_chars(text, text + sizeof text, *value);
  double shortest = 0;
  std::from_chars(text, written.ptr, shortest);
  return json_number(std::optional<double>(shortest));
}

// `value` as compact text. A string that is not valid UTF-8 (a sensor's firmware string is
// whatever bytes it sent) gets U+FFFD for its bad bytes instead of an exception.
inline std::string json_text(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace tiltgate
