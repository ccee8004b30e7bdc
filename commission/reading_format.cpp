#include "commission/reading_format.h"

#include <cmath>
#include <ctime>
#include <fmt/format.h>

#include "mapping/tilt.h"

namespace tiltgate {

namespace {

// `value` with `decimals` places; a value that rounds to zero is "0.000", never "-0.000" (what a
// freshly zeroed sensor shows, and an engineer would take the sign for a reading).
std::string fixed(double value, int decimals) {
  std::string text = fmt::format("{:.{}f}", value, decimals);
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

std::string or_dash(std::optional<double> value, int decimals) {
  return value ? fixed(*value, decimals) : std::string("-");
}

// "1.250 deg", or "-".
std::string degrees_or_dash(std::optional<double> value) {
  return value ? fixed(*value, 3) + " deg" : std::string("-");
}

std::string or_empty(std::optional<double> value) {
  return value ? fixed(*value, 4) : std::string();
}

// RFC 4180: a field with a comma, quote or line break is quoted, its quotes doubled.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::optional<double> unless_nan(double value) {
  return std::isnan(value) ? std::nullopt : std::optional<double>(value);
}

constexpr std::string_view kRowFormat = "{:<8} {:<12} {:>9} {:>9} {:>9}  {:<8} {:>9} {:>7}";

}  // namespace

std::string or_dash(const std::string& text) { return text.empty() ? std::string("-") : text; }

void ReadingRate::update(const SensorState& state) {
  if (!state.reading) return;
  if (seen_ && state.sample_seq == last_seq_) return;
  if (!seen_) first_ = state.reading->taken;
  else ++readings_;
  seen_ = true;
  last_seq_ = state.sample_seq;
  last_ = state.reading->taken;
}

std::optional<double> ReadingRate::per_second() const {
  const std::chrono::duration<double> span = last_ - first_;
  if (readings_ == 0 || span.count() <= 0) return std::nullopt;
  return double(readings_) / span.count();
}

WatchRow snapshot_of(std::uint32_t address, const SensorState& state,
                     SteadyClock::time_point now, std::optional<double> polls_per_second,
                     std::optional<PollResult> outcome) {
  WatchRow s;
  s.address = address;
  s.serial = state.serial;
  s.result = outcome.value_or(state.online ? PollResult::reading : PollResult::silent);
  if (state.reading) {
    s.angle_x = unless_nan(state.reading->angle_x);
    s.angle_y = unless_nan(state.reading->angle_y);
    s.age = std::chrono::duration_cast<std::chrono::milliseconds>(now - state.reading->taken);
  }
  s.polls_per_second = polls_per_second;
  return s;
}

std::optional<double> tilt_of(const WatchRow& snapshot) {
  if (!snapshot.angle_x) return std::nullopt;
  return tilt_degrees(*snapshot.angle_x, snapshot.angle_y.value_or(NAN));
}

std::string_view status_word(PollResult result) {
  switch (result) {
    case PollResult::reading: return "ok";
    case PollResult::refused: return "refused";
    case PollResult::no_reading: return "no-reading";
    case PollResult::silent: break;
  }
  return "no-reply";
}

std::string watch_header() {
  return fmt::format(fmt::runtime(kRowFormat), "ADDRESS", "SERIAL", "X_DEG", "Y_DEG", "TILT_DEG",
                     "STATUS", "AGE_MS", "POLLS/S");
}

std::string watch_row(const WatchRow& s) {
  return fmt::format(fmt::runtime(kRowFormat), s.address, or_dash(s.serial), or_dash(s.angle_x, 3),
                     or_dash(s.angle_y, 3), or_dash(tilt_of(s), 3), status_word(s.result),
                     s.age ? fmt::format("{}", s.age->count()) : std::string("-"),
                     or_dash(s.polls_per_second, 1));
}

std::string iso8601_utc_ms(std::chrono::system_clock::time_point time) {
  using namespace std::chrono;
  const auto whole = floor<seconds>(time);
  const std::time_t t = system_clock::to_time_t(whole);
  std::tm utc{};
  gmtime_r(&t, &utc);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", utc.tm_year + 1900,
                     utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
                     duration_cast<milliseconds>(time - whole).count());
}

std::string csv_header() { return "time,address,serial,x_deg,y_deg,tilt_deg,status\n"; }

std::string csv_line(std::chrono::system_clock::time_point time, const WatchRow& s) {
  const bool fresh = s.result == PollResult::reading;
  const std::optional<double> none;
  return fmt::format("{},{},{},{},{},{},{}\n", iso8601_utc_ms(time), s.address,
                     csv_field(s.serial), or_empty(fresh ? s.angle_x : none),
                     or_empty(fresh ? s.angle_y : none), or_empty(fresh ? tilt_of(s) : none),
                     status_word(s.result));
}

SensorReadingEvent reading_of(std::uint32_t address, std::string_view model,
                              const SensorState& state, SteadyClock::time_point now) {
  const WatchRow row = snapshot_of(address, state, now, std::nullopt);
  SensorReadingEvent reading;
  reading.address = address;
  reading.model = std::string(model);
  reading.device_model = state.model;
  reading.serial = state.serial;
  reading.firmware = state.firmware;
  reading.lock_level = state.protection_level;
  reading.result = row.result;
  reading.angle_x = row.angle_x;
  reading.angle_y = row.angle_y;
  reading.age = row.age;
  reading.polled = std::chrono::system_clock::now();
  return reading;
}

WatchRow watch_row_of(const SensorReadingEvent& reading) {
  WatchRow row;
  row.address = reading.address;
  row.serial = reading.serial;
  row.angle_x = reading.angle_x;
  row.angle_y = reading.angle_y;
  row.result = reading.result;
  row.age = reading.age;
  row.polls_per_second = reading.readings_per_second;
  return row;
}

std::string sensor_info_text(const SensorReadingEvent& reading) {
  const WatchRow s = watch_row_of(reading);
  const std::string lock =
      reading.lock_level ? fmt::format("{}", *reading.lock_level) : std::string("-");
  std::string text;
  text += fmt::format("address:    {}\n", reading.address);
  // The device's own model where it reports one (a device profile's [identity]), then what
  // it is run as.
  if (reading.device_model.empty())
    text += fmt::format("model:      {}\n", reading.model);
  else
    text += fmt::format("model:      {} ({})\n", reading.device_model, reading.model);
  text += fmt::format("serial:     {}\n", or_dash(reading.serial));
  text += fmt::format("firmware:   {}\n", or_dash(reading.firmware));
  text += fmt::format("lock level: {}\n", lock);
  text += fmt::format("angle x:    {}\n", degrees_or_dash(s.angle_x));
  text += fmt::format("angle y:    {}\n", degrees_or_dash(s.angle_y));
  text += fmt::format("tilt:       {}\n", degrees_or_dash(tilt_of(s)));
  return text;
}

std::string sensor_info_text(std::uint32_t address, std::string_view model,
                             const SensorState& state) {
  return sensor_info_text(reading_of(address, model, state, SteadyClock::now()));
}

}  // namespace tiltgate
