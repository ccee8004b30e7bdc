#include "mapping/value_source.h"

#include <array>
#include <cmath>
#include <limits>

#include "mapping/angle_units.h"

namespace tiltgate {
namespace {

using S = ValueSource;

constexpr std::array<Named<ValueSource>, 39> kSources{{
    {"angle_x", S::angle_x},
    {"angle_y", S::angle_y},
    {"angle_x_cdeg", S::angle_x_cdeg},
    {"angle_y_cdeg", S::angle_y_cdeg},
    {"tilt", S::tilt},
    {"raw_counts", S::raw_counts},
    {"raw_temperature", S::raw_temperature},
    {"status", S::status},
    {"online", S::online},
    {"stale", S::stale},
    {"last_write_failed", S::last_write_failed},
    {"identity_unknown", S::identity_unknown},
    {"alarm_active", S::alarm_active},
    {"answers_late", S::answers_late},
    {"alarms", S::alarms},
    {"alarm_x_high", S::alarm_x_high},
    {"alarm_x_low", S::alarm_x_low},
    {"alarm_y_high", S::alarm_y_high},
    {"alarm_y_low", S::alarm_y_low},
    {"alarm_tilt", S::alarm_tilt},
    {"alarm_rate", S::alarm_rate},
    {"age_ms", S::age_ms},
    {"polls_ok", S::polls_ok},
    {"polls_failed", S::polls_failed},
    {"transactions", S::transactions},
    {"timeouts", S::timeouts},
    {"checksum_errors", S::checksum_errors},
    {"io_errors", S::io_errors},
    {"late_replies", S::late_replies},
    {"reply_timeout_ms", S::reply_timeout_ms},
    {"last_nak", S::last_nak},
    {"lock_level", S::lock_level},
    {"bus_address", S::bus_address},
    {"sample_seq", S::sample_seq},
    {"serial", S::serial},
    {"firmware", S::firmware},
    {"model_code", S::model_code},
    {"written", S::written},
    {"setting", S::setting},
}};

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Upside down (mapping/tilt.h): the largest angle from vertical there is.
constexpr double kMaxTilt = 180.0;

ValueRange range(double min, double max) { return ValueRange{min, max, true}; }

ValueRange angle_range(double min_deg, double max_deg, AngleUnit unit) {
  if (unit == AngleUnit::percent_grade) return range(min_deg < 0 ? -kInfinity : 0, kInfinity);
  return range(convert_angle(min_deg, unit), convert_angle(max_deg, unit));
}

}  // namespace

std::span<const Named<ValueSource>> source_names() { return kSources; }

const char* to_string(ValueSource source) {
  if (source == S::bits) return "bits";
  if (source == S::device_value) return "the device's value";
  return name_of(source_names(), source).data();
}

bool is_measurement(ValueSource source) {
  switch (source) {
    case S::angle_x:
    case S::angle_y:
    case S::angle_x_cdeg:
    case S::angle_y_cdeg:
    case S::tilt:
    case S::raw_counts:
    case S::raw_temperature:
    case S::device_value:  // polled with the measurement, stale with it
      return true;
    default:
      return false;
  }
}

bool is_bit_source(ValueSource source) {
  switch (source) {
    case S::online:
    case S::stale:
    case S::last_write_failed:
    case S::identity_unknown:
    case S::alarm_active:
    case S::answers_late:
    case S::alarm_x_high:
    case S::alarm_x_low:
    case S::alarm_y_high:
    case S::alarm_y_low:
    case S::alarm_tilt:
    case S::alarm_rate:
      return true;
    default:
      return false;
  }
}

bool is_integer_source(ValueSource source) {
  if (is_bit_source(source)) return true;
  switch (source) {
    case S::raw_counts:
    case S::raw_temperature:
    case S::status:
    case S::alarms:
    case S::age_ms:
    case S::polls_ok:
    case S::polls_failed:
    case S::transactions:
    case S::timeouts:
    case S::checksum_errors:
    case S::io_errors:
    case S::late_replies:
    case S::reply_timeout_ms:
    case S::last_nak:
    case S::lock_level:
    case S::bus_address:
    case S::sample_seq:
    case S::model_code:
    case S::bits:
      return true;
    default:
      return false;
  }
}

bool is_angle_source(ValueSource source) {
  return source == S::angle_x || source == S::angle_y || source == S::tilt;
}

double convert_angle(double degrees, AngleUnit unit) {
  switch (unit) {
    case AngleUnit::degrees:
      return degrees;
    case AngleUnit::milliradians:
      return degrees_to_milliradians(degrees);
    case AngleUnit::percent_grade:
      return degrees_to_percent_grade(degrees);
  }
  return degrees;
}

ValueRange source_range(ValueSource source, AngleUnit unit) {
  constexpr double kInt32Min = std::numeric_limits<std::int32_t>::min();
  constexpr double kInt32Max = std::numeric_limits<std::int32_t>::max();
  constexpr double kUint32Max = std::numeric_limits<std::uint32_t>::max();
  if (is_bit_source(source)) return range(0, 1);
  switch (source) {
    case S::angle_x:
    case S::angle_y:
      return angle_range(-180, 180, unit);  // the measuring range of any sensor
    case S::angle_x_cdeg:
    case S::angle_y_cdeg:
      return range(-18000, 18000);
    case S::tilt:
      return angle_range(0, kMaxTilt, unit);
    case S::raw_counts:
    case S::raw_temperature:
      return range(kInt32Min, kInt32Max);  // the driver reports int32
    case S::status:
      return range(0, 63);  // six status bits
    case S::alarms:
      return range(0, 63);  // six alarm bits
    case S::polls_ok:
    case S::polls_failed:
    case S::transactions:
    case S::timeouts:
    case S::checksum_errors:
    case S::io_errors:
    case S::late_replies:
      return range(0, kUint32Max);
    // Saturating or 16-bit by nature; bus addresses fit 16 bits on every protocol (driver/family.h).
    case S::age_ms:
    case S::reply_timeout_ms:
    case S::last_nak:
    case S::lock_level:
    case S::bus_address:
    case S::sample_seq:
    case S::model_code:
      return range(0, 65535);
    default:
      return ValueRange{};
  }
}

}  // namespace tiltgate
