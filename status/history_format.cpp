#include "status/history_format.h"

#include <fmt/format.h>

#include <chrono>
#include <optional>

#include "status/json_values.h"

namespace tiltgate {

namespace {

std::string csv_angle(std::optional<float> value) {
  return value ? fmt::format("{}", *value) : "";
}

}  // namespace

std::string iso8601_utc(std::int64_t unix_ms) {
  using namespace std::chrono;
  const sys_time<milliseconds> time{milliseconds(unix_ms)};
  const sys_days day = floor<days>(time);
  const year_month_day date{day};
  const hh_mm_ss<milliseconds> clock{time - day};
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", int(date.year()),
                     unsigned(date.month()), unsigned(date.day()), clock.hours().count(),
                     clock.minutes().count(), clock.seconds().count(), clock.subseconds().count());
}

std::string history_json(const std::vector<AngleSample>& samples) {
  Json out = Json::array();
  // A float's shortest form, 1.25 or -0.003, not its double expansion 1.2500000476837158.
  // The temperature only where there is one: most sensors have none.
  for (const AngleSample& s : samples) {
    Json sample{{"t", s.unix_ms}, {"x", json_float_number(s.x)}, {"y", json_float_number(s.y)}};
    if (s.temperature) sample["temperature"] = json_float_number(s.temperature);
    out.push_back(std::move(sample));
  }
  return json_text(out);
}

std::string history_csv(const std::vector<AngleSample>& samples) {
  std::string out = "time_utc,unix_ms,x_deg,y_deg\r\n";
  for (const AngleSample& s : samples)
    out += fmt::format("{},{},{},{}\r\n", iso8601_utc(s.unix_ms), s.unix_ms, csv_angle(s.x),
                       csv_angle(s.y));
  return out;
}

std::string history_csv_filename(std::string_view sensor) {
  std::string name;
  for (const char c : sensor) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                       (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '_';
    name += plain ? c : '_';
  }
  return name + "-history.csv";
}

}  // namespace tiltgate
