// Inclinometer maths for one sensor, done once per new reading: the mounting correction, the
// tilt magnitude and the alarm flags (mapping/derived_state.h). Pure: no I/O, no clock of its
// own (time comes from Reading::taken).
//
// Mounting, applied in this order:
//   1. swap_axes: (x, y) -> (y, x);
//   2. invert_x / invert_y: that axis changes sign;
//   3. rotate_deg = t: the output X/Y frame is the sensor's frame (after 1 and 2) turned
//      counter-clockwise by t, seen from above (X towards Y is counter-clockwise), i.e. t is the
//      angle from the sensor's X axis to the machine's X axis. The tilt vector keeps its
//      direction, so its components in the turned frame are
//          x' =  x cos t + y sin t
//          y' = -x sin t + y cos t
//      (t = 90: x' = y, y' = -x; t = -90 or 270: x' = -y, y' = x).
//
// The rotation is the small-angle approximation: it treats the two angles as the components
// of a vector in the horizontal plane. The exact transform needs the whole gravity vector,
// which a dual-axis reading does not give unambiguously (whether an axis reports asin(g_x / g)
// or atan(g_x / g_z) is the sensor's business, and the two differ at large tilts). The error
// is second order: with x = y = 10 degrees and t = 45 it is about 0.07 degrees (14.14 instead
// of 14.22 if the sensor reports asin), at 30/30 degrees about 2.6. Multiples of 90 degrees are
// exact whatever the sensor's definition (they only swap and negate axes), so mount sensors
// square where the tilt is large and use swap/invert.
//
// Tilt: the exact angle of the sensor's axis from vertical, tan^2(tilt) = tan^2(x) + tan^2(y)
// over the whole +-180 degree range (mapping/tilt.h), not sqrt(x^2 + y^2). It does not change
// with swap, invert or a turn about the vertical, so it is computed before the rotation and
// carries none of its small-angle error.
//
// Single-axis sensors (angle_y NaN): swap and rotate need two axes and are not applied (the
// config loader rejects them for single-axis models); invert_x applies; angle_y stays NaN and
// tilt = |x|.
//
// Alarms, in degrees after mounting (config/config.h AlarmConfig):
//   - a high alarm (x_high, y_high, tilt_high) sets when its value is > the threshold and
//     clears when it is < threshold - hysteresis_deg; a low alarm (x_low, y_low) sets when its
//     value is < the threshold and clears when it is > threshold + hysteresis_deg; in between,
//     each keeps its state;
//   - the rate alarm sets when |d angle| / dt between two consecutive readings (dt from
//     Reading::taken) is > rate_limit_deg_s on either axis, and clears at the first reading
//     whose rate is <= the limit on every axis: hysteresis_deg is in degrees and has no
//     meaning per second, and a rate that stayed within the limit over one whole sample is
//     the plain reading of "back below". The flag so stays up for at least one sample period;
//   - a NaN value (no angle on that axis) neither sets nor clears the alarms that depend on
//     it: an alarm that is up stays up until a real value clears it. A rate needs two
//     consecutive readings with real values on that axis and a positive dt.
#pragma once

#include "config/config.h"
#include "driver/sensor_state.h"
#include "mapping/derived_state.h"

namespace tiltgate {

class SensorProcessing {
 public:
  explicit SensorProcessing(MountingConfig mounting, AlarmConfig alarms);

  // Call once per new reading (a new SensorState::sample_seq).
  void update(const Reading& reading);
  const DerivedState& derived() const { return derived_; }

 private:
  MountingConfig mounting_;
  AlarmConfig alarms_;
  double cos_ = 1.0;  // of rotate_deg, exact at multiples of 90 degrees
  double sin_ = 0.0;
  DerivedState derived_;
  SteadyClock::time_point previous_taken_{};
};

}  // namespace tiltgate
