// A sensor's reading as JSON (commission_wire/event_json_parts.h), as `info`, `watch` and `set`
// report it, and `watch`'s rounds of them. The poll's result goes by a name of its own, so
// reordering PollResult changes nothing on the wire; `polled` as milliseconds since the epoch
// (finer than that is dropped), the reading's age in milliseconds.
#include <array>
#include <fmt/format.h>
#include <utility>

#include "commission_wire/event_json_parts.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

constexpr std::array<std::pair<PollResult, std::string_view>, 4> kPollResultNames{{
    {PollResult::reading, "reading"},
    {PollResult::refused, "refused"},
    {PollResult::silent, "silent"},
    {PollResult::no_reading, "no_reading"},
}};

std::string_view poll_result_name(PollResult result) {
  for (const auto& [value, name] : kPollResultNames)
    if (value == result) return name;
  return "unknown";  // not a PollResult: reading it back fails, as it should
}

PollResult read_poll_result(const JsonObjectReader& r, std::string_view key) {
  const std::string name = r.string(key);
  for (const auto& [value, known] : kPollResultNames)
    if (known == name) return value;
  throw JsonFieldError(
      fmt::format("field \"{}\": expected reading, refused, silent or no_reading, got \"{}\"",
                  r.path_of(key), name));
}

json optional_ms_json(const std::optional<std::chrono::milliseconds>& ms) {
  return ms ? json(ms->count()) : json(nullptr);
}

// Milliseconds since the epoch, within what system_clock holds (its nanoseconds: 292 years
// either side of 1970), so a wild value is an error instead of an overflow.
std::chrono::system_clock::time_point read_time_point(const JsonObjectReader& r,
                                                      std::string_view key) {
  using std::chrono::milliseconds;
  using Clock = std::chrono::system_clock;
  constexpr auto kLimit =
      std::chrono::duration_cast<milliseconds>(Clock::duration::max()).count();
  const auto ms = r.integer<milliseconds::rep>(key);
  if (ms < -kLimit || ms > kLimit)
    throw JsonFieldError(fmt::format("field \"{}\": expected milliseconds since 1970 within "
                                     "{} either side, got {}",
                                     r.path_of(key), kLimit, ms));
  return Clock::time_point(std::chrono::duration_cast<Clock::duration>(milliseconds(ms)));
}

SensorReadingEvent read_sensor_reading(const JsonObjectReader& r) {
  SensorReadingEvent e;
  read_event_fields(r, e);
  return e;
}

}  // namespace

json event_fields(const SensorReadingEvent& e) {
  using std::chrono::milliseconds;
  return json{
      {"address", e.address},
      {"model", e.model},
      {"device_model", e.device_model},
      {"serial", e.serial},
      {"firmware", e.firmware},
      {"lock_level", json_or_null(e.lock_level)},
      {"result", poll_result_name(e.result)},
      {"status", e.status},
      {"angle_x", json_or_null(e.angle_x)},
      {"angle_y", json_or_null(e.angle_y)},
      {"age_ms", optional_ms_json(e.age)},
      {"readings_per_second", json_or_null(e.readings_per_second)},
      {"polled_ms", std::chrono::duration_cast<milliseconds>(e.polled.time_since_epoch()).count()},
      {"self_report", e.self_report}};
}

void read_event_fields(const JsonObjectReader& r, SensorReadingEvent& e) {
  using std::chrono::milliseconds;
  e.address = r.integer<std::uint32_t>("address");
  e.model = r.string("model");
  e.device_model = r.string("device_model");
  e.serial = r.string("serial");
  e.firmware = r.string("firmware");
  e.lock_level = r.optional_integer<std::uint16_t>("lock_level");
  e.result = read_poll_result(r, "result");
  e.status = r.string("status");
  e.angle_x = r.optional_number("angle_x");
  e.angle_y = r.optional_number("angle_y");
  const auto age = r.optional_integer<milliseconds::rep>("age_ms");
  e.age = age ? std::optional(milliseconds(*age)) : std::nullopt;
  e.readings_per_second = r.optional_number("readings_per_second");
  e.polled = read_time_point(r, "polled_ms");
  e.self_report = r.string("self_report");
}

json event_fields(const WatchRoundEvent& e) {
  json readings = json::array();
  for (const SensorReadingEvent& reading : e.readings) readings.push_back(event_fields(reading));
  return json{{"round", e.round}, {"readings", std::move(readings)}, {"notes", e.notes}};
}

void read_event_fields(const JsonObjectReader& r, WatchRoundEvent& e) {
  e.round = r.integer<int>("round");
  e.readings = r.object_list<SensorReadingEvent>("readings", read_sensor_reading);
  e.notes = r.string_list("notes");
}

}  // namespace tiltgate
