// What the gateway derives from each new reading of a sensor, before the register map sees it:
// angles corrected for the mounting, the tilt magnitude, and alarm flags with their hysteresis
// and rate state. Computed once per reading (line_scheduling/sensor_processing), read by every point.
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
}  // namespace alarm_bit

struct DerivedState {
  double angle_x = NAN;  // degrees, after swap/invert/rotate
  double angle_y = NAN;
  double tilt = NAN;     // degrees from vertical, 0..180 (mapping/tilt.h); |angle_x| on one axis
  std::uint16_t alarms = 0;  // alarm_bit flags
  bool valid = false;        // false until the first reading
};

}  // namespace tiltgate
