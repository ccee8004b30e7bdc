#include "mapping/default_maps.h"

#include <array>
#include <vector>

#include "mapping/dyna_map.h"

namespace tiltgate {
namespace {

// Discrete input 0 is "online"; 1..6 are the alarm flags (mapping/derived_state.h alarm_bit
// order), 0 unless the sensor's [sensor] alarms configure them.
void add_discrete_inputs(std::vector<Point>& points) {
  using S = ValueSource;
  points.push_back(discrete_point("online", 0, S::online, "the sensor answers"));
  points.push_back(discrete_point("alarm_x_high", 1, S::alarm_x_high, "X above alarms.x_high"));
  points.push_back(discrete_point("alarm_x_low", 2, S::alarm_x_low, "X below alarms.x_low"));
  points.push_back(discrete_point("alarm_y_high", 3, S::alarm_y_high, "Y above alarms.y_high"));
  points.push_back(discrete_point("alarm_y_low", 4, S::alarm_y_low, "Y below alarms.y_low"));
  points.push_back(discrete_point("alarm_tilt", 5, S::alarm_tilt, "tilt above alarms.tilt_high"));
  points.push_back(discrete_point("alarm_rate", 6, S::alarm_rate,
                                  "an angle changes faster than alarms.rate_limit_deg_s"));
}

// Registers 6..15 and the identity strings: the same place and meaning on every model, so a
// PLC program written for one sensor family reads the other's health the same way.
void add_status_block(std::vector<Point>& points) {
  using T = PointType;
  using S = ValueSource;
  points.push_back(input_point("status", 6, T::uint16, S::status, "",
                               "bit 0 online, bit 1 stale, bit 2 last write failed, bit 3 identity "
                               "unknown, bit 4 an alarm is active"));
  points.push_back(input_point("age_ms", 7, T::uint16, S::age_ms, "ms",
                               "time since the last good reading, saturating at 65535"));
  points.push_back(
      input_point("polls_ok", 8, T::uint32, S::polls_ok, "", "measurement polls answered"));
  points.push_back(input_point("polls_failed", 10, T::uint32, S::polls_failed, "",
                               "measurement polls not answered"));
  points.push_back(input_point("last_nak", 12, T::uint16, S::last_nak, "",
                               "last NAK code from the sensor, 65535 if none"));
  points.push_back(input_point("lock_level", 13, T::uint16, S::lock_level, "",
                               "sensor lock level, 65535 if unknown"));
  points.push_back(input_point("rs485_address", 14, T::uint16, S::bus_address, "",
                               "the sensor's address on its bus"));
  points.push_back(input_point("sample_seq", 15, T::uint16, S::sample_seq, "",
                               "increments with every new reading"));
  points.push_back(input_point("serial", 16, T::string, S::serial, "",
                               "serial number, 2 characters per register, first in the high byte",
                               10));
  points.push_back(input_point("firmware", 21, T::string, S::firmware, "",
                               "firmware revision, space padded", 7));
  points.push_back(input_point("tilt", 25, T::float32, S::tilt, "deg",
                               "tilt from vertical, tan^2 = tan^2 x + tan^2 y; |x| on one axis"));
  points.push_back(input_point("alarms", 27, T::uint16, S::alarms, "",
                               "bit 0 x high, 1 x low, 2 y high, 3 y low, 4 tilt high, 5 rate; "
                               "0 without [sensor] alarms"));
  add_discrete_inputs(points);
}

RegisterMap rieker_map(bool dual_axis) {
  using T = PointType;
  using S = ValueSource;
  using W = WriteTarget;
  std::vector<Point> points;
  points.push_back(input_point(
      "angle_x", 0, T::float32, S::angle_x, "deg",
      dual_axis ? "X angle after the zero offset and the mounting" : "the single axis angle"));
  points.push_back(input_point(
      "angle_y", 2, T::float32, S::angle_y, "deg",
      dual_axis ? "Y angle after the zero offset and the mounting" : "NaN (single axis)"));
  points.push_back(input_point("angle_x_cdeg", 4, T::int16, S::angle_x_cdeg, "0.01 deg",
                               "X angle in hundredths of a degree, saturating"));
  points.push_back(
      input_point("angle_y_cdeg", 5, T::int16, S::angle_y_cdeg, "0.01 deg",
                  dual_axis ? "Y angle in hundredths of a degree, saturating" : "0 (single axis)"));
  add_status_block(points);
  // Ranges: Rieker function 41 takes 1..6, 38 codes 1..8, addresses 1..65000; a zero offset
  // beyond the +-180 deg measuring range makes no sense.
  points.push_back(holding_point("filter", 0, T::uint16, W::filter, 1, 6, "",
                                 "Set Filter Response 1 (fast, noisy) .. 6 (slow, quiet)"));
  points.push_back(holding_point("zero_x", 1, T::float32, W::zero_x, -180, 180, "deg",
                                 "Set Zero To Value, axis 1"));
  if (dual_axis) {
    points.push_back(holding_point("zero_y", 3, T::float32, W::zero_y, -180, 180, "deg",
                                   "Set Zero To Value, axis 2"));
  }
  points.push_back(holding_point("command", 5, T::uint16, W::command, 1, 3, "",
                                 "1 zero to current angle (temporary), 2 (permanent), 3 restart"));
  points.push_back(holding_point("baud_code", 6, T::uint16, W::baud_code, 1, 8, "",
                                 "Set Baud 1..8, takes effect after restart"));
  points.push_back(holding_point("rs485_address", 7, T::uint16, W::bus_address, 1, 65000, "",
                                 "Set Address; the gateway follows the sensor"));
  return RegisterMap(std::move(points));
}

RegisterMap h6_map() { return rieker_map(true); }
RegisterMap h4360_map() { return rieker_map(false); }

struct BuiltInMap {
  std::string_view model;
  RegisterMap (*build)();
};

// One row per model with a built-in map.
constexpr std::array<BuiltInMap, 3> kBuiltInMaps{{
    {"h6", h6_map},
    {"h4360", h4360_map},
    {"dyna", dyna_default_map},
}};

}  // namespace

RegisterMap default_map(std::string_view model) {
  for (const BuiltInMap& m : kBuiltInMaps)
    if (m.model == model) return m.build();
  return RegisterMap();
}

std::vector<std::string_view> models_with_default_maps() {
  std::vector<std::string_view> models;
  for (const BuiltInMap& m : kBuiltInMaps) models.push_back(m.model);
  return models;
}

}  // namespace tiltgate
