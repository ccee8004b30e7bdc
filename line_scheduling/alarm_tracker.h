// A sensor's alarms at two levels, with their hold time and latches (docs/monitoring.md,
// "Alarms"). Pure: fed the values of each new reading with the reading's time, it keeps each
// alarm's state and says which set or cleared.
//
// Each alarm is one kind (x_high, x_low, y_high, y_low, tilt_high, rate, displacement_high) at
// one level (warning: the thresholds at the top of [[sensor]] alarms; danger: alarms.danger),
// and each is on its own:
//   - a high alarm's value is past its threshold when > threshold, back when < threshold -
//     hysteresis; a low alarm's when < threshold and > threshold + hysteresis; the rate's when
//     > its limit and <= it (a rate has no hysteresis: docs/monitoring.md says why). Between
//     the two, nothing changes;
//   - it sets once its value has been past the threshold at every reading for `hold`
//     (for_ms), measured from the first such reading to this one, and clears once it has been
//     back as long. With hold 0 a single reading does it;
//   - a reading without the value (NaN: no Y on one axis, no rate on the first reading)
//     neither sets nor clears, and starts the hold over: an alarm must be seen to hold.
//
// Latches, per kind, either level: a kind latches when it sets and stays latched until it has
// been acknowledged (acknowledge(), a PLC's coil write) and is no longer set at any level. An
// acknowledged kind that sets again needs a new acknowledgement.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "config/config.h"
#include "driver/sensor_state.h"
#include "mapping/derived_state.h"

namespace tiltgate {

// In alarm_bit order (mapping/derived_state.h): kind k is bit 1 << k.
enum class AlarmKind : std::uint8_t { x_high, x_low, y_high, y_low, tilt_high, rate,
                                      displacement_high };
inline constexpr std::size_t kAlarmKinds = 7;
enum class AlarmLevel : std::uint8_t { warning, danger };

// "x_high", ..., "rate", "displacement_high": the names events and the API use.
const char* to_string(AlarmKind kind);
const char* to_string(AlarmLevel level);

// The values the alarms look at, NaN where there is none.
struct AlarmValues {
  double x = NAN;
  double y = NAN;
  double tilt = NAN;
  double rate = NAN;             // the faster axis's |d angle / dt|, degrees per second
  double displacement_mm = NAN;  // from the baseline
};

// One alarm that set or cleared, at the reading whose time is `taken`.
struct AlarmTransition {
  AlarmKind kind = AlarmKind::x_high;
  AlarmLevel level = AlarmLevel::warning;
  bool set = false;
  double value = NAN;      // the value at that reading
  double threshold = NAN;  // the level's threshold
  SteadyClock::time_point taken{};
};

class AlarmTracker {
 public:
  explicit AlarmTracker(const AlarmConfig& config);

  // One new reading's values; the alarms that set or cleared at it are appended to `changed`.
  void update(const AlarmValues& values, SteadyClock::time_point taken,
              std::vector<AlarmTransition>& changed);
  // Latched kinds that are no longer set are let go; those still set go once they clear.
  void acknowledge();

  std::uint16_t warning() const { return flags(AlarmLevel::warning); }
  std::uint16_t danger() const { return flags(AlarmLevel::danger); }
  std::uint16_t latched() const { return latched_; }
  std::uint16_t unacknowledged() const { return std::uint16_t(latched_ & ~acknowledged_); }

 private:
  struct Rule {
    std::optional<double> threshold;
    bool high = true;        // set above the threshold (false: below)
    double hysteresis = 0;   // how far back clears
    bool active = false;
    // When the value was first seen past (or, while active, back) at every reading since.
    std::optional<SteadyClock::time_point> since;
  };

  std::uint16_t flags(AlarmLevel level) const;
  Rule& rule(AlarmKind kind, AlarmLevel level) {
    return rules_[std::size_t(level)][std::size_t(kind)];
  }

  std::chrono::milliseconds hold_;
  std::array<std::array<Rule, kAlarmKinds>, 2> rules_{};
  std::uint16_t latched_ = 0;
  std::uint16_t acknowledged_ = 0;  // latched kinds acknowledged while still set
};

}  // namespace tiltgate
