#include "config/alarm_options.h"

#include <fmt/format.h>

#include "mapping/model_capabilities.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;

namespace {

// Every angle a sensor reports is within +-180 degrees; a threshold beyond can never trip.
constexpr double kMaxAlarmAngle = 180.0;
// A day of for_ms: longer is a mistake (a structure that moves for a day has long been seen).
constexpr std::int64_t kMaxHoldMs = 86'400'000;

void check_below(TableReader& sub, const std::optional<double>& low,
                 const std::optional<double>& high, std::string_view low_key,
                 std::string_view high_key) {
  if (low && high && !(*low < *high))
    sub.error(low_key, fmt::format("{} {} is not below {} {}", low_key, *low, high_key, *high));
}

// One level's thresholds from `sub`: the keys both levels share.
void read_thresholds(TableReader& sub, AlarmThresholds& a, bool one_axis, bool has_lever,
                     const SensorConfig& sensor) {
  a.x_high = sub.number_in("x_high", -kMaxAlarmAngle, kMaxAlarmAngle);
  a.x_low = sub.number_in("x_low", -kMaxAlarmAngle, kMaxAlarmAngle);
  a.y_high = sub.number_in("y_high", -kMaxAlarmAngle, kMaxAlarmAngle);
  a.y_low = sub.number_in("y_low", -kMaxAlarmAngle, kMaxAlarmAngle);
  for (std::string_view key : {"y_high", "y_low"})
    if (one_axis && sub.has(key))
      sub.error(key, fmt::format("needs two axes; model \"{}\" has one", sensor.model));
  a.tilt_high = sub.number_in("tilt_high", 0.0, kMaxAlarmAngle);
  if (auto v = sub.number("rate_limit_deg_s")) {
    if (*v <= 0.0)
      sub.error("rate_limit_deg_s", fmt::format("{} is not above 0 degrees per second", *v));
    else
      a.rate_limit_deg_s = *v;
  }
  if (auto v = sub.number("displacement_high_mm")) {
    if (*v <= 0.0)
      sub.error("displacement_high_mm", fmt::format("{} is not above 0 mm", *v));
    else if (!has_lever)
      sub.error("displacement_high_mm",
                "needs the sensor's lever_m (the height the displacement is measured at)");
    else
      a.displacement_high_mm = *v;
  }
  check_below(sub, a.x_low, a.x_high, "x_low", "x_high");
  check_below(sub, a.y_low, a.y_high, "y_low", "y_high");
}

// The danger level lies beyond the warning level: a danger that sets before its warning is a
// swapped pair of numbers.
void check_beyond(TableReader& danger, const std::optional<double>& warning_value,
                  const std::optional<double>& danger_value, std::string_view key, bool high) {
  if (!warning_value || !danger_value) return;
  const bool beyond = high ? *danger_value > *warning_value : *danger_value < *warning_value;
  if (!beyond)
    danger.error(key, fmt::format("danger {} {} is not {} the warning level's {}", key,
                                  *danger_value, high ? "above" : "below", *warning_value));
}

}  // namespace

void read_alarms(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                 FamilyList families) {
  const toml::table* table = in.table("alarms");
  if (table == nullptr) return;
  TableReader sub(*table, in.located().key_path("alarms"), errors);
  AlarmConfig& a = sensor.alarms;
  const bool one_axis = in.located().valid("model") && model_axes(families, sensor.model) == 1;
  const bool has_lever = sensor.lever_m.has_value();
  read_thresholds(sub, a, one_axis, has_lever, sensor);
  if (auto v = sub.number_in("hysteresis_deg", 0.0, kMaxAlarmAngle)) a.hysteresis_deg = *v;
  if (auto v = sub.number_in("hysteresis_mm", 0.0, 1e6)) a.hysteresis_mm = *v;
  if (auto ms = sub.integer("for_ms", 0, kMaxHoldMs)) a.hold = std::chrono::milliseconds(*ms);
  if (const toml::table* danger_table = sub.table("danger")) {
    TableReader danger(*danger_table, sub.located().key_path("danger"), errors);
    read_thresholds(danger, a.danger, one_axis, has_lever, sensor);
    const AlarmThresholds& w = a;
    const AlarmThresholds& d = a.danger;
    check_beyond(danger, w.x_high, d.x_high, "x_high", true);
    check_beyond(danger, w.x_low, d.x_low, "x_low", false);
    check_beyond(danger, w.y_high, d.y_high, "y_high", true);
    check_beyond(danger, w.y_low, d.y_low, "y_low", false);
    check_beyond(danger, w.tilt_high, d.tilt_high, "tilt_high", true);
    check_beyond(danger, w.rate_limit_deg_s, d.rate_limit_deg_s, "rate_limit_deg_s", true);
    check_beyond(danger, w.displacement_high_mm, d.displacement_high_mm, "displacement_high_mm",
                 true);
    danger.reject_unknown_keys();
  }
  sub.reject_unknown_keys();
}

}  // namespace tiltgate::config
