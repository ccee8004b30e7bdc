#include "line_scheduling/alarm_tracker.h"

#include <cmath>

namespace tiltgate {

namespace {

double value_of(const AlarmValues& values, AlarmKind kind) {
  switch (kind) {
    case AlarmKind::x_high:
    case AlarmKind::x_low: return values.x;
    case AlarmKind::y_high:
    case AlarmKind::y_low: return values.y;
    case AlarmKind::tilt_high: return values.tilt;
    case AlarmKind::rate: return values.rate;
    case AlarmKind::displacement_high: return values.displacement_mm;
  }
  return NAN;
}

const std::optional<double>& threshold_of(const AlarmThresholds& t, AlarmKind kind) {
  switch (kind) {
    case AlarmKind::x_high: return t.x_high;
    case AlarmKind::x_low: return t.x_low;
    case AlarmKind::y_high: return t.y_high;
    case AlarmKind::y_low: return t.y_low;
    case AlarmKind::tilt_high: return t.tilt_high;
    case AlarmKind::rate: return t.rate_limit_deg_s;
    case AlarmKind::displacement_high: break;
  }
  return t.displacement_high_mm;
}

double hysteresis_of(const AlarmConfig& config, AlarmKind kind) {
  if (kind == AlarmKind::rate) return 0.0;
  if (kind == AlarmKind::displacement_high) return config.hysteresis_mm;
  return config.hysteresis_deg;
}

std::uint16_t bit_of(AlarmKind kind) { return std::uint16_t(1u << unsigned(kind)); }

}  // namespace

const char* to_string(AlarmKind kind) {
  switch (kind) {
    case AlarmKind::x_high: return "x_high";
    case AlarmKind::x_low: return "x_low";
    case AlarmKind::y_high: return "y_high";
    case AlarmKind::y_low: return "y_low";
    case AlarmKind::tilt_high: return "tilt_high";
    case AlarmKind::rate: return "rate";
    case AlarmKind::displacement_high: return "displacement_high";
  }
  return "?";
}

const char* to_string(AlarmLevel level) {
  return level == AlarmLevel::danger ? "danger" : "warning";
}

AlarmTracker::AlarmTracker(const AlarmConfig& config) : hold_(config.hold) {
  for (std::size_t k = 0; k < kAlarmKinds; ++k) {
    const auto kind = AlarmKind(k);
    const bool high = kind != AlarmKind::x_low && kind != AlarmKind::y_low;
    rules_[0][k] = Rule{threshold_of(config, kind), high, hysteresis_of(config, kind), false, {}};
    rules_[1][k] = Rule{threshold_of(config.danger, kind), high, hysteresis_of(config, kind),
                        false, {}};
  }
}

void AlarmTracker::update(const AlarmValues& values, SteadyClock::time_point taken,
                          std::vector<AlarmTransition>& changed) {
  for (std::size_t level = 0; level < 2; ++level) {
    for (std::size_t k = 0; k < kAlarmKinds; ++k) {
      Rule& r = rules_[level][k];
      if (!r.threshold) continue;
      const auto kind = AlarmKind(k);
      const double value = value_of(values, kind);
      const double t = *r.threshold;
      // NaN compares false both ways: neither past nor back.
      bool past = false;
      bool back = false;
      if (kind == AlarmKind::rate) {
        past = value > t;
        back = value <= t;
      } else if (r.high) {
        past = value > t;
        back = value < t - r.hysteresis;
      } else {
        past = value < t;
        back = value > t + r.hysteresis;
      }
      const bool moving = r.active ? back : past;
      if (!moving) {
        r.since.reset();
        continue;
      }
      if (!r.since) r.since = taken;
      if (taken - *r.since < hold_) continue;
      r.since.reset();
      r.active = !r.active;
      changed.push_back(AlarmTransition{kind, AlarmLevel(level), r.active, value, t, taken});
      const std::uint16_t bit = bit_of(kind);
      if (r.active) {
        latched_ |= bit;
        acknowledged_ &= std::uint16_t(~bit);
      } else if ((acknowledged_ & bit) && !((warning() | danger()) & bit)) {
        latched_ &= std::uint16_t(~bit);
        acknowledged_ &= std::uint16_t(~bit);
      }
    }
  }
}

void AlarmTracker::acknowledge() {
  const std::uint16_t set = warning() | danger();
  latched_ &= set;
  acknowledged_ |= latched_;
}

std::uint16_t AlarmTracker::flags(AlarmLevel level) const {
  std::uint16_t bits = 0;
  for (std::size_t k = 0; k < kAlarmKinds; ++k)
    if (rules_[std::size_t(level)][k].active) bits |= bit_of(AlarmKind(k));
  return bits;
}

}  // namespace tiltgate
