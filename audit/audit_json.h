// An audit record as JSON: one object per record, as the trail stores it on disk and as
// `GET /api/audit` answers (an array of them, newest first). Keys: "time_ms" (Unix ms),
// "door", "who", "sensor", "setting", "old" (absent when not known), "new", "result"; on disk also "prev"
// (audit/audit_chain.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "audit/audit_record.h"

namespace tiltgate {

std::string audit_json(const std::vector<AuditRecord>& records);
std::string audit_record_json(const AuditRecord& record);
// As the trail stores it: with "prev", the chain's hash of the record before it
// (audit/audit_chain.h).
std::string audit_record_json(const AuditRecord& record, std::string_view prev);
// The "prev" of a stored record; none when it has none (or is no JSON object).
std::optional<std::string> audit_record_prev(std::string_view text);
// None for text that is not such an object.
std::optional<AuditRecord> audit_record_from_json(std::string_view text);

}  // namespace tiltgate
