#include "audit/audit_text.h"

#include <ctime>
#include <fmt/format.h>

namespace tiltgate {

std::string audit_text(const AuditRecord& record) {
  const std::string change = record.old_value.empty()
                                 ? fmt::format("{} = {}", record.setting, record.new_value)
                                 : fmt::format("{} {} -> {}", record.setting, record.old_value,
                                               record.new_value);
  return fmt::format("door {}, who {}: {}{}{}: {}", record.origin.door, record.origin.who,
                     record.sensor, record.sensor.empty() ? "" : " ", change, record.result);
}

std::string audit_time_text(std::int64_t unix_ms) {
  const std::time_t seconds = unix_ms / 1000;
  std::tm local{};
  localtime_r(&seconds, &local);
  char date[40];
  char zone[8];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%S", &local);
  std::strftime(zone, sizeof zone, "%z", &local);
  return fmt::format("{}.{:03}{}", date, unix_ms % 1000, zone);
}

}  // namespace tiltgate
