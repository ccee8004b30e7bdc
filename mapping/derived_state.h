// What the gateway derives from each new reading of a sensor, before the register map sees it:
// angles corrected for the mounting, the tilt magnitude, readings relative to the baseline,
// the displacement, and alarm flags with their hysteresis, hold and rate state. Computed once
// per reading (line_scheduling/sensor_processing), read by every point.
#pragma once

#include <cmath>
#include <cstdint>

namespace tiltgate {

namespace alarm_bit {
constexpr std::uint16_t x_high = 1 << 0;
constexpr std::uint16_t x_low = 1 << 1;
constexpr std::uint16_t y_high = 1 << 2;
constexpr std::uint16_t y_low = 1 << 3;
constexpr std::uint16_t tilt_high = 1 << 4;
constexpr std::uint16_t rate = 1 << 5;
constexpr std::uint16_t displacement = 1 << 6;
}  // namespace alarm_bit

struct DerivedState {
  double angle_x = NAN;  // degrees, after swap/invert/rotate
  double angle_y = NAN;
  double tilt = NAN;     // degrees from vertical, 0..180 (mapping/tilt.h); |angle_x| on one axis
  // Degrees from the sensor's baseline ([[sensor]] baseline, or one set since), after mounting.
  double relative_x = NAN;
  double relative_y = NAN;
  // Millimetres at [[sensor]] lever_m from the baseline (line_scheduling/sensor_processing.h);
  // NaN without lever_m. displacement_mm is the length of (x, y); |x| on one axis.
  double displacement_x_mm = NAN;
  double displacement_y_mm = NAN;
  double displacement_mm = NAN;
  // alarm_bit flags: the kinds set at either level; those set at the danger level; those
  // latched until a PLC acknowledges them and they clear, and those of them not acknowledged
  // yet (line_scheduling/alarm_tracker.h).
  std::uint16_t alarms = 0;
  std::uint16_t alarms_danger = 0;
  std::uint16_t alarms_latched = 0;
  std::uint16_t alarms_unacknowledged = 0;
  // When the reading's reply arrived, UTC milliseconds (0 before the first), and whether the
  // system clock was synchronised then (docs/operations.md, "The clock").
  std::int64_t taken_unix_ms = 0;
  bool clock_synchronised = true;
  bool valid = false;        // false until the first reading
};

}  // namespace tiltgate
