#include "line_scheduling/sensor_processing.h"

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

// Sets `bit` when `set` holds, clears it when `clear` holds, else leaves it.
void latch(std::uint16_t& alarms, std::uint16_t bit, bool set, bool clear) {
  if (set) alarms |= bit;
  else if (clear) alarms &= std::uint16_t(~bit);
}

// A high alarm: above the threshold sets, below threshold - hysteresis clears. NaN compares
// false both ways, so it neither sets nor clears.
void high_alarm(std::uint16_t& alarms, std::uint16_t bit, const std::optional<double>& threshold,
                double hysteresis, double value) {
  if (!threshold) {
    alarms &= std::uint16_t(~bit);
    return;
  }
  latch(alarms, bit, value > *threshold, value < *threshold - hysteresis);
}

void low_alarm(std::uint16_t& alarms, std::uint16_t bit, const std::optional<double>& threshold,
               double hysteresis, double value) {
  if (!threshold) {
    alarms &= std::uint16_t(~bit);
    return;
  }
  latch(alarms, bit, value < *threshold, value > *threshold + hysteresis);
}

// |d angle| / dt in degrees per second; NaN when either value is NaN.
double rate_of(double previous, double current, double seconds) {
  return std::fabs(current - previous) / seconds;
}

}  // namespace

SensorProcessing::SensorProcessing(MountingConfig mounting, AlarmConfig alarms)
    : mounting_(mounting), alarms_(alarms) {
  const CosSin turn = cos_sin_degrees(mounting_.rotate_deg);
  cos_ = turn.cos;
  sin_ = turn.sin;
}

void SensorProcessing::update(const Reading& reading) {
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

  std::uint16_t alarms = derived_.alarms;
  const double h = alarms_.hysteresis_deg;
  high_alarm(alarms, alarm_bit::x_high, alarms_.x_high, h, x);
  low_alarm(alarms, alarm_bit::x_low, alarms_.x_low, h, x);
  high_alarm(alarms, alarm_bit::y_high, alarms_.y_high, h, y);
  low_alarm(alarms, alarm_bit::y_low, alarms_.y_low, h, y);
  high_alarm(alarms, alarm_bit::tilt_high, alarms_.tilt_high, h, tilt);

  if (!alarms_.rate_limit_deg_s) {
    alarms &= std::uint16_t(~alarm_bit::rate);
  } else if (derived_.valid && reading.taken > previous_taken_) {
    const double seconds = std::chrono::duration<double>(reading.taken - previous_taken_).count();
    const double rate_x = rate_of(derived_.angle_x, x, seconds);
    const double rate_y = rate_of(derived_.angle_y, y, seconds);
    const double limit = *alarms_.rate_limit_deg_s;
    const bool over = rate_x > limit || rate_y > limit;
    // Back below only when every axis that has a rate shows it, and at least one has.
    const bool measured = !std::isnan(rate_x) || !std::isnan(rate_y);
    const bool within = measured && !(rate_x > limit) && !(rate_y > limit);
    latch(alarms, alarm_bit::rate, over, within);
  }

  derived_.angle_x = x;
  derived_.angle_y = y;
  derived_.tilt = tilt;
  derived_.alarms = alarms;
  derived_.valid = true;
  previous_taken_ = reading.taken;
}

}  // namespace tiltgate
