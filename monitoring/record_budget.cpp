#include "monitoring/record_budget.h"

#include <fmt/format.h>

#include <algorithm>

#include "monitoring/record_format.h"

namespace tiltgate::monitoring {

std::uint64_t record_day_file_bytes(std::uint32_t interval_s) {
  constexpr std::uint64_t kDaySeconds = 86'400;
  const std::uint64_t interval = std::max<std::uint32_t>(interval_s, 1);
  const std::uint64_t intervals = (kDaySeconds + interval - 1) / interval;
  const std::uint64_t bytes = kFileHeaderBytes + kRecordBytes * intervals;
  return (bytes + kDiskBlockBytes - 1) / kDiskBlockBytes * kDiskBlockBytes;
}

std::uint64_t record_bytes_per_sensor(std::uint32_t keep_days, std::uint32_t interval_s) {
  return (static_cast<std::uint64_t>(keep_days) + 1) * record_day_file_bytes(interval_s);
}

std::uint64_t record_bytes_total(std::uint64_t sensors, std::uint32_t keep_days,
                                 std::uint32_t interval_s) {
  return sensors * record_bytes_per_sensor(keep_days, interval_s);
}

std::string disk_bytes_text(std::uint64_t bytes) {
  if (bytes < 1000) return fmt::format("{} bytes", bytes);
  const double value = static_cast<double>(bytes);
  if (bytes < 1'000'000) return fmt::format("{:.1f} kB", value / 1e3);
  if (bytes < 1'000'000'000) return fmt::format("{:.1f} MB", value / 1e6);
  return fmt::format("{:.1f} GB", value / 1e9);
}

std::string record_budget_text(std::uint64_t sensors, std::uint32_t keep_days,
                               std::uint32_t interval_s) {
  return fmt::format("long record: {} {} x {} {} at {} s: {}", sensors,
                     sensors == 1 ? "sensor" : "sensors", keep_days, keep_days == 1 ? "day" : "days",
                     interval_s,
                     disk_bytes_text(record_bytes_total(sensors, keep_days, interval_s)));
}

}  // namespace tiltgate::monitoring
