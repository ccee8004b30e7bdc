#include "config/sensor_options.h"

#include <fmt/format.h>

#include "mapping/model_capabilities.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;
namespace {

// The sensor's model has one axis: keys about a second axis are mistakes.
bool single_axis(const TableReader& in, const SensorConfig& sensor, FamilyList families) {
  return in.located().valid("model") && model_axes(families, sensor.model) == 1;
}

void reject_on_single_axis(TableReader& sub, std::string_view key, const SensorConfig& sensor) {
  sub.error(key, fmt::format("needs two axes; model \"{}\" has one", sensor.model));
}

// Every angle a sensor reports is within +-180 degrees; a threshold beyond can never trip.
constexpr double kMaxAngle = 180.0;

void check_order(TableReader& sub, const std::optional<double>& low,
                 const std::optional<double>& high, std::string_view low_key,
                 std::string_view high_key) {
  if (low && high && !(*low < *high))
    sub.error(low_key, fmt::format("{} {} is not below {} {}", low_key, *low, high_key, *high));
}

}  // namespace

void read_mounting(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                   FamilyList families) {
  const toml::table* table = in.table("mounting");
  if (table == nullptr) return;
  TableReader sub(*table, in.located().key_path("mounting"), errors);
  MountingConfig& m = sensor.mounting;
  const bool one_axis = single_axis(in, sensor, families);
  if (auto v = sub.boolean("swap_axes")) {
    if (*v && one_axis) reject_on_single_axis(sub, "swap_axes", sensor);
    m.swap_axes = *v;
  }
  if (auto v = sub.boolean("invert_x")) m.invert_x = *v;
  if (auto v = sub.boolean("invert_y")) {
    if (*v && one_axis) reject_on_single_axis(sub, "invert_y", sensor);
    m.invert_y = *v;
  }
  if (auto v = sub.number_in("rotate_deg", -360.0, 360.0)) {
    if (*v != 0.0 && one_axis) reject_on_single_axis(sub, "rotate_deg", sensor);
    m.rotate_deg = *v;
  }
  sub.reject_unknown_keys();
}

void read_alarms(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                 FamilyList families) {
  const toml::table* table = in.table("alarms");
  if (table == nullptr) return;
  TableReader sub(*table, in.located().key_path("alarms"), errors);
  AlarmConfig& a = sensor.alarms;
  const bool one_axis = single_axis(in, sensor, families);
  a.x_high = sub.number_in("x_high", -kMaxAngle, kMaxAngle);
  a.x_low = sub.number_in("x_low", -kMaxAngle, kMaxAngle);
  a.y_high = sub.number_in("y_high", -kMaxAngle, kMaxAngle);
  a.y_low = sub.number_in("y_low", -kMaxAngle, kMaxAngle);
  for (std::string_view key : {"y_high", "y_low"})
    if (one_axis && sub.has(key)) reject_on_single_axis(sub, key, sensor);
  a.tilt_high = sub.number_in("tilt_high", 0.0, kMaxAngle);
  if (auto v = sub.number_in("hysteresis_deg", 0.0, kMaxAngle)) a.hysteresis_deg = *v;
  if (auto v = sub.number("rate_limit_deg_s")) {
    if (*v <= 0.0)
      sub.error("rate_limit_deg_s", fmt::format("{} is not above 0 degrees per second", *v));
    else
      a.rate_limit_deg_s = *v;
  }
  check_order(sub, a.x_low, a.x_high, "x_low", "x_high");
  check_order(sub, a.y_low, a.y_high, "y_low", "y_high");
  sub.reject_unknown_keys();
}

void read_offline(TableReader& in, SensorConfig& sensor) {
  const auto policy = in.choice("offline", {"exception", "last", "substitute"});
  if (policy == "last") sensor.offline = OfflineRead::last_value;
  if (policy == "substitute") sensor.offline = OfflineRead::substitute;
  // NaN is a fine substitute for float points; integer points show their nan_value for it.
  if (auto value = in.number("substitute", Presence::optional, true)) {
    if (sensor.offline != OfflineRead::substitute && in.located().usable("offline"))
      in.error("substitute", "applies with offline = \"substitute\" only");
    sensor.substitute = *value;
  }
}

}  // namespace tiltgate::config
