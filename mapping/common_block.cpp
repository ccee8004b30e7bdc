#include "mapping/common_block.h"

namespace tiltgate {
namespace {

using T = PointType;
using S = ValueSource;
using W = WriteTarget;

// What an integer angle reads when there is no angle (the Y axis of a single-axis model).
constexpr double kNoAngleCdeg = -32768;

Point cdeg_point(std::string name, std::uint16_t address, ValueSource source,
                 std::string description) {
  Point p = input_point(std::move(name), address, T::int16, source, "0.01 deg",
                        std::move(description));
  p.nan_value = kNoAngleCdeg;
  return p;
}

void add_angles(std::vector<Point>& points, const CommonBlockModel& m) {
  const bool two = m.dual_axis;
  points.push_back(input_point("angle_x", 0, T::float32, S::angle_x, "deg", m.angle_x_description));
  points.push_back(input_point("angle_y", 2, T::float32, S::angle_y, "deg",
                               !two                             ? "NaN (single axis)"
                               : !m.angle_y_description.empty() ? m.angle_y_description
                                                                : "Y angle after the zero offset and the mounting"));
  points.push_back(cdeg_point("angle_x_cdeg", 4, S::angle_x_cdeg,
                              "X angle in hundredths of a degree, saturating"));
  points.push_back(cdeg_point("angle_y_cdeg", 5, S::angle_y_cdeg,
                              two ? "Y angle in hundredths of a degree, saturating"
                                  : "-32768 (single axis)"));
}

// The input registers 6..51 of every model, after the angles: one row each.
struct InputRow {
  const char* name;
  std::uint16_t address;
  PointType type;
  ValueSource source;
  const char* units;
  const char* description;
  std::uint16_t chars = 0;  // string points: characters
};

constexpr InputRow kStatusIdentityAndCounters[] = {
    {"status", 6, T::uint16, S::status, "",
     "bit 0 online, bit 1 stale, bit 2 last write failed, bit 3 identity unknown, bit 4 an "
     "alarm is active, bit 5 answers late, bit 6 wrong device, bit 7 standby, bit 8 the "
     "reading was taken while the clock was unsynchronised"},
    {"age_ms", 7, T::uint16, S::age_ms, "ms",
     "time since the last good reading, saturating at 65535"},
    {"polls_ok", 8, T::uint32, S::polls_ok, "", "measurement polls answered"},
    {"polls_failed", 10, T::uint32, S::polls_failed, "", "measurement polls not answered"},
    {"last_nak", 12, T::uint16, S::last_nak, "",
     "last NAK code from the sensor, 65535 if none (or no NAKs)"},
    {"lock_level", 13, T::uint16, S::lock_level, "",
     "sensor lock level, 65535 if unknown (or no locks)"},
    {"bus_address", 14, T::uint16, S::bus_address, "", "the sensor's address on its bus"},
    {"sample_seq", 15, T::uint16, S::sample_seq, "", "increments with every new reading"},
    {"serial", 16, T::string, S::serial, "",
     "serial number, 2 characters per register, first in the high byte", 10},
    // 8 characters: the firmware texts of the sensors served have 7 or fewer, or are free text;
    // function 43 reports it in full.
    {"firmware", 21, T::string, S::firmware, "",
     "firmware revision, first 8 characters, space padded", 8},
    {"tilt", 25, T::float32, S::tilt, "deg",
     "tilt from vertical, tan^2 = tan^2 x + tan^2 y; |x| on one axis"},
    {"alarms", 27, T::uint16, S::alarms, "",
     "alarms set at either level: bit 0 x high, 1 x low, 2 y high, 3 y low, 4 tilt high, 5 "
     "rate, 6 displacement; 0 without [sensor] alarms"},
    {"timeouts", 28, T::uint32, S::timeouts, "", "exchanges that got no valid reply in time"},
    {"checksum_errors", 30, T::uint32, S::checksum_errors, "",
     "replies dropped for a bad CRC or LRC"},
    {"late_replies", 32, T::uint32, S::late_replies, "",
     "replies that came after the reply time-out"},
    {"io_errors", 34, T::uint32, S::io_errors, "", "exchanges lost to a port failure"},
    {"reply_timeout_ms", 36, T::uint16, S::reply_timeout_ms, "ms",
     "the reply time-out in use for this sensor"},
    // Described by the map's builder, which knows every model (mapping/map_definition.h).
    {"model_code", 37, T::uint16, S::model_code, "", ""},
    // The monitoring (docs/monitoring.md): readings from the baseline, the displacement and
    // the alarm levels, after the older registers so that their addresses stay.
    {"relative_x", 38, T::float32, S::relative_x, "deg", "X from the baseline"},
    {"relative_y", 40, T::float32, S::relative_y, "deg", "Y from the baseline; NaN on one axis"},
    {"displacement_x_mm", 42, T::float32, S::displacement_x_mm, "mm",
     "X displacement at lever_m from the baseline; NaN without lever_m"},
    {"displacement_y_mm", 44, T::float32, S::displacement_y_mm, "mm",
     "Y displacement at lever_m from the baseline; NaN without lever_m or on one axis"},
    {"displacement_mm", 46, T::float32, S::displacement_mm, "mm",
     "the length of the displacement; NaN without lever_m"},
    {"alarms_danger", 48, T::uint16, S::alarms_danger, "",
     "alarms set at the danger level, bits as register 27"},
    {"alarms_latched", 49, T::uint16, S::alarms_latched, "",
     "alarms latched until acknowledged (coil 0) and clear, bits as register 27"},
    {"temperature", 50, T::float32, S::temperature, "degC",
     "the sensor's temperature where it reports one (docs/monitoring.md, Temperature); NaN "
     "otherwise"},
};

void add_status_identity_and_counters(std::vector<Point>& points) {
  for (const InputRow& row : kStatusIdentityAndCounters)
    points.push_back(input_point(row.name, row.address, row.type, row.source, row.units,
                                 row.description, row.chars));
}

// Discrete input 0 is "online"; 1..6 are the alarm flags (mapping/derived_state.h alarm_bit
// order), 0 unless the sensor's [sensor] alarms configure them; 7 is "wrong device" (status
// bit 6), 8 "standby" (status bit 7), and 9..12 the monitoring's, each after the others so
// that the addresses of the older ones stay.
struct DiscreteRow {
  const char* name;
  ValueSource source;
  const char* description;
};

constexpr DiscreteRow kDiscreteInputs[] = {
    {"online", S::online, "the sensor answers"},
    {"alarm_x_high", S::alarm_x_high, "X above alarms.x_high"},
    {"alarm_x_low", S::alarm_x_low, "X below alarms.x_low"},
    {"alarm_y_high", S::alarm_y_high, "Y above alarms.y_high"},
    {"alarm_y_low", S::alarm_y_low, "Y below alarms.y_low"},
    {"alarm_tilt", S::alarm_tilt, "tilt above alarms.tilt_high"},
    {"alarm_rate", S::alarm_rate, "an angle changes faster than alarms.rate_limit_deg_s"},
    {"wrong_device", S::wrong_device,
     "another device than the configured serial answers at the sensor's address"},
    {"standby", S::standby,
     "this gateway is the standby of a redundant pair: the values are heard from the active "
     "gateway's polls"},
    {"alarm_displacement", S::alarm_displacement,
     "the displacement above alarms.displacement_high_mm"},
    {"alarm_danger", S::alarm_danger, "an alarm is set at the danger level"},
    {"alarm_unacknowledged", S::alarm_unacknowledged,
     "an alarm latched since the last acknowledgement (coil 0)"},
    {"clock_unsynchronised", S::clock_unsynchronised,
     "the last reading was taken while the system clock was not synchronised"},
};

void add_discrete_inputs(std::vector<Point>& points) {
  std::uint16_t address = 0;
  for (const DiscreteRow& row : kDiscreteInputs)
    points.push_back(discrete_point(row.name, address++, row.source, row.description));
}

// Coil 0: the PLC acknowledges the latched alarms (line_scheduling/alarm_tracker.h).
void add_coils(std::vector<Point>& points) {
  points.push_back(make_point("acknowledge_alarms", RegisterTable::coil, 0, T::boolean,
                              S::acknowledge_alarms, "",
                              "reads 1 while an alarm awaits acknowledgement; write 1 to "
                              "acknowledge every latched alarm"));
}

// `units` for a model without the setting; a model's own come from its descriptor.
Point setting_point(std::string name, std::uint16_t address, PointType type, WriteTarget target,
                    const std::optional<SettingDescriptor>& setting, std::string units) {
  if (!setting) {
    Point p = unavailable_holding_point(
        std::move(name), address, type, "not available on this model: reads 65535 (NaN as a float)");
    p.units = std::move(units);
    return p;
  }
  Point p = holding_point(std::move(name), address, type, target, setting->min, setting->max,
                         std::string(setting->unit), std::string(setting->description));
  p.role = setting->role;
  p.operator_values.assign(setting->operator_values.begin(), setting->operator_values.end());
  return p;
}

void add_settings(std::vector<Point>& points, const CommonBlockModel& m) {
  points.push_back(setting_point("filter", 0, T::uint16, W::filter, m.filter, ""));
  points.push_back(setting_point("zero_x", 1, T::float32, W::zero_x, m.zero_x, "deg"));
  points.push_back(setting_point("zero_y", 3, T::float32, W::zero_y, m.zero_y, "deg"));
  Point command = setting_point("command", 5, T::uint16, W::command, m.command, "");
  if (m.command) command.nan_value = 0;  // a command is no setting: reads 0, "no command"
  points.push_back(std::move(command));
  points.push_back(setting_point("baud_code", 6, T::uint16, W::baud_code, m.baud_code, ""));
  points.push_back(
      setting_point("bus_address", 7, T::uint16, W::bus_address, m.bus_address, ""));
}

}  // namespace

bool yields_to_map_points(const Point& p) {
  switch (p.table) {
    case RegisterTable::coil: return p.address == 0 && p.source == S::acknowledge_alarms;
    case RegisterTable::discrete: return p.address >= 9 && p.address <= 12;
    case RegisterTable::input: return p.address >= 38 && p.address <= 51;
    case RegisterTable::holding: break;
  }
  return false;
}

bool names_point(std::string_view given, std::string_view name) {
  return given == name || (given == kFormerAddressPointName && name == kAddressPointName);
}

std::vector<Point> common_block(const CommonBlockModel& model) {
  std::vector<Point> points;
  add_coils(points);
  add_discrete_inputs(points);
  add_angles(points, model);
  add_status_identity_and_counters(points);
  add_settings(points, model);
  return points;
}

}  // namespace tiltgate
