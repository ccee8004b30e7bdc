#include "mapping/value_source.h"

#include <cstddef>
#include <cstdint>
#include <cmath>
#include <limits>
#include <vector>

#include "mapping/angle_units.h"

namespace tiltgate {
namespace {

using S = ValueSource;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kInt32Min = std::numeric_limits<std::int32_t>::min();
constexpr double kInt32Max = std::numeric_limits<std::int32_t>::max();
constexpr double kUint32Max = std::numeric_limits<std::uint32_t>::max();
// Upside down (mapping/tilt.h): the largest angle from vertical there is.
constexpr double kMaxTilt = 180.0;

// What a source is, one row per source in the enum's order: what a map file calls it, whether
// reading it needs a fresh measurement, whether it is one bit, a whole number or degrees, and
// the range its value is documented to have (in degrees for the angles).
enum Kind : std::uint8_t {
  kMeasurement = 1 << 0,
  kBit = 1 << 1,
  kInteger = 1 << 2,  // bits included
  kAngle = 1 << 3,
  kRanged = 1 << 4,
};

struct SourceRow {
  std::string_view name;  // empty: not named in map files
  ValueSource source;
  std::uint8_t kind;
  double min = 0;
  double max = 0;
};

constexpr std::uint8_t kFlag = kBit | kInteger | kRanged;
constexpr std::uint8_t kCounter = kInteger | kRanged;

constexpr SourceRow kRows[] = {
    {"angle_x", S::angle_x, kMeasurement | kAngle | kRanged, -180, 180},  // any sensor's range
    {"angle_y", S::angle_y, kMeasurement | kAngle | kRanged, -180, 180},
    {"angle_x_cdeg", S::angle_x_cdeg, kMeasurement | kRanged, -18000, 18000},
    {"angle_y_cdeg", S::angle_y_cdeg, kMeasurement | kRanged, -18000, 18000},
    {"tilt", S::tilt, kMeasurement | kAngle | kRanged, 0, kMaxTilt},
    // An angle less its baseline, both within +-180.
    {"relative_x", S::relative_x, kMeasurement | kAngle | kRanged, -360, 360},
    {"relative_y", S::relative_y, kMeasurement | kAngle | kRanged, -360, 360},
    // 1000 x lever_m (at most 10 km) x a difference of sines (at most 2); the length sqrt(2) more.
    {"displacement_x_mm", S::displacement_x_mm, kMeasurement | kRanged, -2e7, 2e7},
    {"displacement_y_mm", S::displacement_y_mm, kMeasurement | kRanged, -2e7, 2e7},
    {"displacement_mm", S::displacement_mm, kMeasurement | kRanged, 0, 2.83e7},
    // The driver reports int32.
    {"raw_counts", S::raw_counts, kMeasurement | kCounter, kInt32Min, kInt32Max},
    {"raw_temperature", S::raw_temperature, kMeasurement | kCounter, kInt32Min, kInt32Max},
    // Every model's, as angle_y is: NaN where the sensor reports none (the common block has it
    // for all). The range: what any inclinometer's operating range is within, with margin
    // (theirs: -40..85 degC).
    {"temperature", S::temperature, kMeasurement | kRanged, -100, 200},
    {"status", S::status, kCounter, 0, 511},  // nine status bits
    {"online", S::online, kFlag, 0, 1},
    {"stale", S::stale, kFlag, 0, 1},
    {"last_write_failed", S::last_write_failed, kFlag, 0, 1},
    {"identity_unknown", S::identity_unknown, kFlag, 0, 1},
    {"alarm_active", S::alarm_active, kFlag, 0, 1},
    {"answers_late", S::answers_late, kFlag, 0, 1},
    {"wrong_device", S::wrong_device, kFlag, 0, 1},
    {"standby", S::standby, kFlag, 0, 1},
    {"clock_unsynchronised", S::clock_unsynchronised, kFlag, 0, 1},
    {"alarms", S::alarms, kCounter, 0, 127},  // seven alarm bits
    {"alarm_x_high", S::alarm_x_high, kFlag, 0, 1},
    {"alarm_x_low", S::alarm_x_low, kFlag, 0, 1},
    {"alarm_y_high", S::alarm_y_high, kFlag, 0, 1},
    {"alarm_y_low", S::alarm_y_low, kFlag, 0, 1},
    {"alarm_tilt", S::alarm_tilt, kFlag, 0, 1},
    {"alarm_rate", S::alarm_rate, kFlag, 0, 1},
    {"alarm_displacement", S::alarm_displacement, kFlag, 0, 1},
    {"alarm_danger", S::alarm_danger, kFlag, 0, 1},
    {"alarm_unacknowledged", S::alarm_unacknowledged, kFlag, 0, 1},
    {"alarms_danger", S::alarms_danger, kCounter, 0, 127},
    {"alarms_latched", S::alarms_latched, kCounter, 0, 127},
    {"acknowledge_alarms", S::acknowledge_alarms, kFlag, 0, 1},
    // Saturating or 16-bit by nature; bus addresses fit 16 bits on every protocol
    // (driver/family.h).
    {"age_ms", S::age_ms, kCounter, 0, 65535},
    {"polls_ok", S::polls_ok, kCounter, 0, kUint32Max},
    {"polls_failed", S::polls_failed, kCounter, 0, kUint32Max},
    {"transactions", S::transactions, kCounter, 0, kUint32Max},
    {"timeouts", S::timeouts, kCounter, 0, kUint32Max},
    {"checksum_errors", S::checksum_errors, kCounter, 0, kUint32Max},
    {"io_errors", S::io_errors, kCounter, 0, kUint32Max},
    {"late_replies", S::late_replies, kCounter, 0, kUint32Max},
    {"reply_timeout_ms", S::reply_timeout_ms, kCounter, 0, 65535},
    {"last_nak", S::last_nak, kCounter, 0, 65535},
    {"lock_level", S::lock_level, kCounter, 0, 65535},
    {"bus_address", S::bus_address, kCounter, 0, 65535},
    {"sample_seq", S::sample_seq, kCounter, 0, 65535},
    {"serial", S::serial, 0},
    {"firmware", S::firmware, 0},
    {"model_code", S::model_code, kCounter, 0, 65535},
    {"written", S::written, 0},
    {"setting", S::setting, 0},
    // Polled with the measurement, stale with it; its range is the device's.
    {"", S::device_value, kMeasurement},
    {"", S::bits, kInteger},
};

constexpr const SourceRow& row_of(ValueSource source) {
  return kRows[static_cast<std::size_t>(source)];
}

// The table is in the enum's order, every source once.
constexpr bool rows_in_enum_order() {
  for (std::size_t i = 0; i < std::size(kRows); ++i)
    if (static_cast<std::size_t>(kRows[i].source) != i) return false;
  return static_cast<std::size_t>(S::bits) + 1 == std::size(kRows);
}
static_assert(rows_in_enum_order());

bool has(ValueSource source, std::uint8_t kind) { return (row_of(source).kind & kind) != 0; }

ValueRange range(double min, double max) { return ValueRange{min, max, true}; }

}  // namespace

std::span<const Named<ValueSource>> source_names() {
  static const std::vector<Named<ValueSource>> names = [] {
    std::vector<Named<ValueSource>> out;
    for (const SourceRow& row : kRows)
      if (!row.name.empty()) out.push_back({row.name, row.source});
    return out;
  }();
  return names;
}

const char* to_string(ValueSource source) {
  if (source == S::bits) return "bits";
  if (source == S::device_value) return "the device's value";
  return row_of(source).name.data();
}

bool is_measurement(ValueSource source) { return has(source, kMeasurement); }
bool is_bit_source(ValueSource source) { return has(source, kBit); }
bool is_integer_source(ValueSource source) { return has(source, kInteger); }
bool is_angle_source(ValueSource source) { return has(source, kAngle); }

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
  const SourceRow& row = row_of(source);
  if (!has(source, kRanged)) return ValueRange{};
  if (!has(source, kAngle)) return range(row.min, row.max);
  if (unit == AngleUnit::percent_grade) return range(row.min < 0 ? -kInfinity : 0, kInfinity);
  return range(convert_angle(row.min, unit), convert_angle(row.max, unit));
}

}  // namespace tiltgate
