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
// Baseline and displacement (docs/monitoring.md, "Baseline and displacement"): the relative
// angles are the angles after mounting minus the baseline's; the displacement at lever_m
// metres is, per axis, 1000 * lever_m * (sin a - sin a0) millimetres for an angle a and its
// baseline a0: the horizontal movement of a point lever_m above the pivot of a rigid member
// that turns from a0 to a. displacement_mm is the length of the two (|x| on one axis).
//
// Alarms, in degrees after mounting (rate: per second; displacement: mm), at two levels with
// their hold time and latches: line_scheduling/alarm_tracker.h. The rate is the faster axis's
// |d angle| / dt between two consecutive readings (dt from Reading::taken): it needs two
// readings with real values on an axis and a positive dt, else it is NaN (neither sets nor
// clears).
#pragma once

#include <optional>
#include <vector>

#include "driver/sensor_state.h"
#include "line_scheduling/alarm_tracker.h"
#include "mapping/derived_state.h"

namespace tiltgate {

class SensorProcessing {
 public:
  SensorProcessing(MountingConfig mounting, const AlarmConfig& alarms,
                   std::optional<double> lever_m = {}, Baseline baseline = {});

  // Call once per new reading (a new SensorState::sample_seq), with its UTC time as the bus
  // made it from Reading::taken. The alarms that set or cleared at it are in changed() until
  // the next call.
  void update(const Reading& reading, std::int64_t taken_unix_ms = 0,
              bool clock_synchronised = true);
  const DerivedState& derived() const { return derived_; }
  const std::vector<AlarmTransition>& changed() const { return changed_; }

  // A new baseline, from the next reading on (the relative values of the last one are
  // recomputed now, so what is served agrees with it at once).
  void set_baseline(Baseline baseline);
  const Baseline& baseline() const { return baseline_; }
  // A PLC acknowledged the latched alarms (AlarmTracker::acknowledge()).
  void acknowledge_alarms();

 private:
  void relate_to_baseline();
  void publish_alarms();

  MountingConfig mounting_;
  AlarmTracker alarms_;
  std::optional<double> lever_m_;
  Baseline baseline_;
  double cos_ = 1.0;  // of rotate_deg, exact at multiples of 90 degrees
  double sin_ = 0.0;
  DerivedState derived_;
  std::vector<AlarmTransition> changed_;
  SteadyClock::time_point previous_taken_{};
};

}  // namespace tiltgate
