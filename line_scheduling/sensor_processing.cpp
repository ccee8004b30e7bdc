#include "line_scheduling/sensor_processing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include "mapping/tilt.h"

namespace tiltgate {

namespace {

struct CosSin {
  double cos;
  double sin;
};

// cos and sin of an angle in degrees, exactly 0 / +-1 at multiples of 90 degrees so that a
// quarter turn only swaps and negates (cos(pi / 2) in doubles is 6e-17, not 0).
CosSin cos_sin_degrees(double degrees) {
  const double quarter_turns = degrees / 90.0;
  if (quarter_turns == std::round(quarter_turns)) {
    const long quadrant = ((std::lround(std::fmod(quarter_turns, 4.0)) % 4) + 4) % 4;
    constexpr CosSin exact[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    return exact[quadrant];
  }
  const double radians = degrees * std::numbers::pi / 180.0;
  return {std::cos(radians), std::sin(radians)};
}

// |d angle| / dt in degrees per second; NaN when either value is NaN.
double rate_of(double previous, double current, double seconds) {
  return std::fabs(current - previous) / seconds;
}

// The faster of two rates, NaN only when neither is known.
double faster(double a, double b) {
  if (std::isnan(a)) return b;
  if (std::isnan(b)) return a;
  return std::max(a, b);
}

// Millimetres a point `lever_m` above the pivot moves horizontally when the member turns from
// `from` to `to` degrees (docs/monitoring.md, "Baseline and displacement").
double displacement_mm(double lever_m, double from, double to) {
  constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
  return 1000.0 * lever_m * (std::sin(to * kRadiansPerDegree) - std::sin(from * kRadiansPerDegree));
}

}  // namespace

SensorProcessing::SensorProcessing(MountingConfig mounting, const AlarmConfig& alarms,
                                   std::optional<double> lever_m, Baseline baseline)
    : mounting_(mounting), alarms_(alarms), lever_m_(lever_m), baseline_(baseline) {
  const CosSin turn = cos_sin_degrees(mounting_.rotate_deg);
  cos_ = turn.cos;
  sin_ = turn.sin;
}

void SensorProcessing::update(const Reading& reading, std::int64_t taken_unix_ms,
                              bool clock_synchronised) {
  changed_.clear();
  derived_.taken_unix_ms = taken_unix_ms;
  derived_.clock_synchronised = clock_synchronised;
  double x = reading.angle_x;
  double y = reading.angle_y;
  const bool dual_axis = !std::isnan(y);
  if (dual_axis && mounting_.swap_axes) std::swap(x, y);
  if (mounting_.invert_x) x = -x;
  if (dual_axis && mounting_.invert_y) y = -y;
  // Exact (mapping/tilt.h) and invariant under the turn about the vertical, so taken before
  // the small-angle rotation below, which would otherwise leak its error into it.
  const double tilt = tilt_degrees(x, y);
  if (dual_axis) {
    const double turned_x = x * cos_ + y * sin_;
    const double turned_y = -x * sin_ + y * cos_;
    x = turned_x;
    y = turned_y;
  }

  AlarmValues values{x, y, tilt, NAN, NAN};
  if (derived_.valid && reading.taken > previous_taken_) {
    const double seconds = std::chrono::duration<double>(reading.taken - previous_taken_).count();
    values.rate = faster(rate_of(derived_.angle_x, x, seconds), rate_of(derived_.angle_y, y, seconds));
  }
  derived_.angle_x = x;
  derived_.angle_y = y;
  derived_.tilt = tilt;
  derived_.valid = true;
  previous_taken_ = reading.taken;
  relate_to_baseline();
  values.displacement_mm = derived_.displacement_mm;
  alarms_.update(values, reading.taken, changed_);
  publish_alarms();
}

void SensorProcessing::set_baseline(Baseline baseline) {
  baseline_ = baseline;
  if (derived_.valid) relate_to_baseline();
}

void SensorProcessing::acknowledge_alarms() {
  alarms_.acknowledge();
  publish_alarms();
}

void SensorProcessing::relate_to_baseline() {
  DerivedState& d = derived_;
  d.relative_x = d.angle_x - baseline_.x;
  d.relative_y = d.angle_y - baseline_.y;  // NaN on one axis
  if (!lever_m_) return;
  d.displacement_x_mm = displacement_mm(*lever_m_, baseline_.x, d.angle_x);
  d.displacement_y_mm = displacement_mm(*lever_m_, baseline_.y, d.angle_y);
  d.displacement_mm = std::isnan(d.displacement_y_mm)
                          ? std::fabs(d.displacement_x_mm)
                          : std::hypot(d.displacement_x_mm, d.displacement_y_mm);
}

void SensorProcessing::publish_alarms() {
  derived_.alarms = alarms_.warning() | alarms_.danger();
  derived_.alarms_danger = alarms_.danger();
  derived_.alarms_latched = alarms_.latched();
  derived_.alarms_unacknowledged = alarms_.unacknowledged();
}

}  // namespace tiltgate
