// A change made through the console, as one audit record (audit/audit_record.h): door
// "console", who the user is, the time the trail's (AuditTrail::record). Nothing without a trail.
#pragma once

#include <string>

#include "audit/audit_trail.h"

namespace tiltgate {

inline void record_console_change(AuditTrail* audit, const std::string& user, std::string sensor,
                                  std::string setting, std::string old_value,
                                  std::string new_value, std::string result) {
  if (audit == nullptr) return;
  AuditRecord record;
  record.origin = WriteOrigin{"console", user};
  record.sensor = std::move(sensor);
  record.setting = std::move(setting);
  record.old_value = std::move(old_value);
  record.new_value = std::move(new_value);
  record.result = std::move(result);
  audit->record(std::move(record));
}

}  // namespace tiltgate
