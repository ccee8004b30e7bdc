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

void read_baseline(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                   FamilyList families) {
  if (auto lever = in.number("lever_m")) {
    if (*lever <= 0.0 || *lever > 10'000.0)
      in.error("lever_m", fmt::format("{} is out of range, expected above 0 and at most 10000 "
                                      "(metres)", *lever));
    else
      sensor.lever_m = *lever;
  }
  const toml::table* table = in.table("baseline");
  if (table == nullptr) return;
  TableReader sub(*table, in.located().key_path("baseline"), errors);
  Baseline baseline;
  if (auto x = sub.number_in("x", -kMaxAngle, kMaxAngle)) baseline.x = *x;
  if (auto y = sub.number_in("y", -kMaxAngle, kMaxAngle)) {
    if (single_axis(in, sensor, families) && *y != 0.0) reject_on_single_axis(sub, "y", sensor);
    baseline.y = *y;
  }
  sub.reject_unknown_keys();
  sensor.baseline = baseline;
}

void read_burst(TableReader& in, SensorConfig& sensor) {
  // An hour of polling as fast as the line allows is already a long event's record.
  if (auto s = in.integer("burst_s", 0, 3600)) sensor.burst = std::chrono::seconds(*s);
  if (auto s = in.integer("pre_trigger_s", 0, 600)) {
    if (sensor.burst.count() == 0 && in.located().usable("burst_s"))
      in.error("pre_trigger_s", "applies with burst_s only");
    sensor.pre_trigger = std::chrono::seconds(*s);
  }
  if (auto rate = in.number("burst_rate_deg_s")) {
    if (*rate <= 0.0)
      in.error("burst_rate_deg_s", fmt::format("{} is not above 0 degrees per second", *rate));
    else if (sensor.burst.count() == 0 && in.located().usable("burst_s"))
      in.error("burst_rate_deg_s", "applies with burst_s only");
    else
      sensor.burst_rate_deg_s = *rate;
  }
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
