// An audit record as JSON: one object per record, as the trail stores it on disk and as
// `GET /api/audit` answers (an array of them, newest first). Keys: "time_ms" (Unix ms),
// "door", "who", "sensor", "setting", "old" (absent when not known), "new", "result".
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "audit/audit_record.h"

namespace tiltgate {

std::string audit_json(const std::vector<AuditRecord>& records);
std::string audit_record_json(const AuditRecord& record);
// None for text that is not such an object.
std::optional<AuditRecord> audit_record_from_json(std::string_view text);

}  // namespace tiltgate
