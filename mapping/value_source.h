// What a point shows: every value a driver's SensorState offers, and what the gateway derives
// from it (mapping/derived_state.h), with the range each one is documented to have so that a
// map can be checked for types too small to hold it.
#pragma once

#include <cstdint>
#include <span>

#include "mapping/point_types.h"

namespace tiltgate {

enum class ValueSource : std::uint8_t {
  angle_x,  // degrees (after mounting, when configured)
  angle_y,
  angle_x_cdeg,  // hundredths of a degree
  angle_y_cdeg,
  tilt,  // degrees, magnitude of (angle_x, angle_y); |angle_x| on one axis
  relative_x,  // degrees from the baseline (mapping/derived_state.h)
  relative_y,
  displacement_x_mm,  // millimetres at lever_m from the baseline
  displacement_y_mm,
  displacement_mm,    // the length of (x, y)
  raw_counts,
  raw_temperature,
  temperature,  // degrees Celsius, where the sensor reports a temperature
  status,  // status_bit flags (mapping/sensor_view.h)
  online,  // one bit each: the status bits ...
  stale,
  last_write_failed,
  identity_unknown,
  alarm_active,
  answers_late,
  wrong_device,
  standby,
  clock_unsynchronised,
  alarms,  // ... and the alarm_bit flags, as one integer or one bit each
  alarm_x_high,
  alarm_x_low,
  alarm_y_high,
  alarm_y_low,
  alarm_tilt,
  alarm_rate,
  alarm_displacement,
  alarm_danger,          // any alarm at the danger level
  alarm_unacknowledged,  // any latched alarm not acknowledged yet
  alarms_danger,         // the alarm_bit flags set at the danger level
  alarms_latched,        // the alarm_bit flags latched (set since, not acknowledged and clear)
  // Coil: reads as alarm_unacknowledged; writing 1 acknowledges every latched alarm (the one
  // coil a PLC writes, handled by the gateway, never sent to the sensor).
  acknowledge_alarms,
  age_ms,
  polls_ok,
  polls_failed,
  transactions,
  timeouts,
  checksum_errors,
  io_errors,
  late_replies,
  reply_timeout_ms,  // the reply time-out in use (adapts upward after late replies)
  last_nak,    // 65535 when none
  lock_level,  // 65535 when unknown
  bus_address,
  sample_seq,
  serial,
  firmware,
  model_code,  // ModelDescriptor::model_code (mapping/model_capabilities.h)
  written,  // holding registers: the last value written through the gateway
  // The setting named by the point's `write` as the sensor holds it (read back, or
  // acknowledged); NaN while unknown, and always on a point without `write` (a setting the
  // model does not have).
  setting,
  // One of the sensor's own values (driver/device_value.h): Point::device_value names it. A
  // map file names it by that name, not by this source's.
  device_value,
  bits,     // an integer made of one-bit sources (Point::bits), not named in files
};

// Every built-in source a map file may name (not `bits`, which is spelt as a key of its own,
// nor `device_value`, which a file spells as the value's own name).
std::span<const Named<ValueSource>> source_names();
const char* to_string(ValueSource source);

// Whether reading the point needs a fresh measurement (see OfflineRead) or is diagnostic and
// always readable, so a PLC can see why the data is missing. Alarm flags are diagnostic: they
// keep the state of the last reading, and the status word says whether that is stale.
bool is_measurement(ValueSource source);
// A source whose value is one bit (0 or 1): what a coil or discrete input shows.
bool is_bit_source(ValueSource source);
// A whole number whose single bits can be picked out with `bit = N`.
bool is_integer_source(ValueSource source);
// Degrees that a point may show in another AngleUnit (not the fixed *_cdeg forms).
bool is_angle_source(ValueSource source);

// The documented range of a source's value, in `unit` for angle sources; infinite bounds where
// the value has none (percent grade). Strings, `written` and `setting` have no numeric range:
// empty, and so have a sensor's own values (their range is the device's).
struct ValueRange {
  double min = 0;
  double max = 0;
  bool known = false;
};
ValueRange source_range(ValueSource source, AngleUnit unit);

// Degrees in another unit (mapping/angle_units.h: percent grade is NaN beyond +-90 degrees).
double convert_angle(double degrees, AngleUnit unit);

}  // namespace tiltgate
