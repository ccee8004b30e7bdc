#include "mapping/source_values.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "mapping/tilt.h"

namespace tiltgate {
namespace {

using S = ValueSource;

bool derived_valid(const SensorView& v) { return v.derived != nullptr && v.derived->valid; }

double angle(const SensorView& v, bool x) {
  if (derived_valid(v)) return x ? v.derived->angle_x : v.derived->angle_y;
  if (!v.state.reading) return NAN;
  return x ? v.state.reading->angle_x : v.state.reading->angle_y;
}

// Without derived state: the tilt of the raw reading (the mounting does not change it),
// |x| on a single-axis sensor.
double tilt(const SensorView& v) {
  if (derived_valid(v)) return v.derived->tilt;
  return tilt_degrees(angle(v, true), angle(v, false));
}

// A value derived from the last reading; NaN before one.
double derived_or_nan(const SensorView& v, double DerivedState::*member) {
  const DerivedState* d = v.valid_derived();
  return d != nullptr ? d->*member : NAN;
}

// Flags of the derived state (alarm_bit); 0 before a reading.
std::uint16_t derived_flags(const SensorView& v, std::uint16_t DerivedState::*member) {
  const DerivedState* d = v.valid_derived();
  return d != nullptr ? d->*member : 0;
}

double optional_int(const std::optional<std::int32_t>& value) {
  return value ? double(*value) : NAN;
}

double bit_of(std::uint16_t flags, std::uint16_t bit) { return (flags & bit) != 0 ? 1 : 0; }

// The sensor's own value `index` from its last reading; NaN before one, or unmatched.
double device_value(const SensorView& v, std::size_t index) {
  if (!v.state.reading || index >= v.state.reading->device_values.size()) return NAN;
  return v.state.reading->device_values[index];
}

// NaN (the point's nan_value) while the driver does not know the setting, and on a point that
// names none. A sensor's own writable value is known from every poll.
double setting_value(const Point& p, const SensorView& v) {
  if (!p.write) return NAN;
  if (p.write->is_device_value()) return device_value(v, p.write->device_index());
  return v.state.settings.get(*p.write).value_or(NAN);
}

// The measurement: angles, tilt and the raw reading; none for other sources.
std::optional<double> measured_value(ValueSource source, const SensorView& v) {
  const auto& reading = v.state.reading;
  switch (source) {
    case S::angle_x: return angle(v, true);
    case S::angle_y: return angle(v, false);
    case S::angle_x_cdeg: return angle(v, true) * 100.0;
    case S::angle_y_cdeg: return angle(v, false) * 100.0;
    case S::tilt: return tilt(v);
    case S::relative_x: return derived_or_nan(v, &DerivedState::relative_x);
    case S::relative_y: return derived_or_nan(v, &DerivedState::relative_y);
    case S::displacement_x_mm: return derived_or_nan(v, &DerivedState::displacement_x_mm);
    case S::displacement_y_mm: return derived_or_nan(v, &DerivedState::displacement_y_mm);
    case S::displacement_mm: return derived_or_nan(v, &DerivedState::displacement_mm);
    case S::raw_counts: return reading ? optional_int(reading->raw_counts) : NAN;
    case S::raw_temperature: return reading ? optional_int(reading->raw_temperature) : NAN;
    case S::temperature: return reading ? reading->temperature_c.value_or(NAN) : NAN;
    default: return std::nullopt;
  }
}

// The status word and its bits; none for other sources.
std::optional<double> status_value(ValueSource source, const SensorView& v) {
  switch (source) {
    case S::status: return v.status();
    case S::online: return bit_of(v.status(), status_bit::online);
    case S::stale: return bit_of(v.status(), status_bit::stale);
    case S::last_write_failed: return bit_of(v.status(), status_bit::last_write_failed);
    case S::identity_unknown: return bit_of(v.status(), status_bit::identity_unknown);
    case S::alarm_active: return bit_of(v.status(), status_bit::alarm_active);
    case S::answers_late: return bit_of(v.status(), status_bit::answers_late);
    case S::wrong_device: return bit_of(v.status(), status_bit::wrong_device);
    case S::standby: return bit_of(v.status(), status_bit::standby);
    case S::clock_unsynchronised: return bit_of(v.status(), status_bit::clock_unsynchronised);
    default: return std::nullopt;
  }
}

// The alarm word and its bits; none for other sources.
std::optional<double> alarm_value(ValueSource source, const SensorView& v) {
  switch (source) {
    case S::alarms: return v.alarms();
    case S::alarm_x_high: return bit_of(v.alarms(), alarm_bit::x_high);
    case S::alarm_x_low: return bit_of(v.alarms(), alarm_bit::x_low);
    case S::alarm_y_high: return bit_of(v.alarms(), alarm_bit::y_high);
    case S::alarm_y_low: return bit_of(v.alarms(), alarm_bit::y_low);
    case S::alarm_tilt: return bit_of(v.alarms(), alarm_bit::tilt_high);
    case S::alarm_rate: return bit_of(v.alarms(), alarm_bit::rate);
    case S::alarm_displacement: return bit_of(v.alarms(), alarm_bit::displacement);
    case S::alarm_danger: return derived_flags(v, &DerivedState::alarms_danger) != 0 ? 1 : 0;
    case S::alarm_unacknowledged:
    case S::acknowledge_alarms:
      return derived_flags(v, &DerivedState::alarms_unacknowledged) != 0 ? 1 : 0;
    case S::alarms_danger: return derived_flags(v, &DerivedState::alarms_danger);
    case S::alarms_latched: return derived_flags(v, &DerivedState::alarms_latched);
    default: return std::nullopt;
  }
}

// The line's view of the sensor: counters, timing, the last refusal and what it is; none for
// other sources.
std::optional<double> line_value(ValueSource source, const SensorView& v) {
  const SensorState& s = v.state;
  const SensorCounters& c = s.counters;
  switch (source) {
    case S::age_ms: return v.age_ms();
    case S::polls_ok: return c.polls_ok;
    case S::polls_failed: return c.polls_failed;
    case S::transactions: return c.transactions;
    case S::timeouts: return c.timeouts;
    case S::checksum_errors: return c.checksum_errors;
    case S::io_errors: return c.io_errors;
    case S::late_replies: return c.late_replies;
    case S::reply_timeout_ms: return double(std::min<long long>(s.reply_timeout.count(), 65535));
    case S::last_nak: return c.last_refusal ? *c.last_refusal : 65535;
    case S::lock_level: return s.protection_level ? *s.protection_level : 65535;
    case S::bus_address: return s.bus_address;
    case S::sample_seq: return s.sample_seq;
    case S::model_code: return v.model_code;
    default: return std::nullopt;
  }
}

}  // namespace

double source_value(ValueSource source, const SensorView& v) {
  if (const std::optional<double> value = measured_value(source, v)) return *value;
  if (const std::optional<double> value = status_value(source, v)) return *value;
  if (const std::optional<double> value = alarm_value(source, v)) return *value;
  if (const std::optional<double> value = line_value(source, v)) return *value;
  // serial, firmware, written, setting, device_value and bits are no number of the view
  // (point_value() reads the last four).
  return NAN;
}

double point_value(const Point& p, const SensorView& v) {
  if (p.source == S::bits) {
    std::uint32_t packed = 0;
    for (std::size_t i = 0; i < p.bits.size(); ++i)
      if (p.bits[i] && source_value(*p.bits[i], v) != 0) packed |= std::uint32_t(1) << i;
    return packed;
  }
  const double value = p.source == S::setting        ? setting_value(p, v)
                       : p.source == S::device_value ? device_value(v, p.device_index)
                                                     : source_value(p.source, v);
  if (p.bit) {
    if (std::isnan(value)) return 0;
    // Integer sources only (checked when the map is loaded); signed ones in two's complement.
    return double((std::uint64_t(std::int64_t(value)) >> *p.bit) & 1);
  }
  if (is_angle_source(p.source)) return convert_angle(value, p.angle_unit);
  return value;
}

}  // namespace tiltgate
