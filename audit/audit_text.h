// An audit record as one line of text, for the journal ("audit: " before it) and for
// `tiltgate audit`:
//   door modbus, who 10.0.0.5:50122: bus1/tilt1 filter 2 -> 3: ack
//   door control socket, who user root (uid 0, pid 4242): bus1/223 address 223 -> 5: ack
#pragma once

#include <string>

#include "audit/audit_record.h"

namespace tiltgate {

std::string audit_text(const AuditRecord& record);
// The record's time as local ISO 8601 with milliseconds: "2026-12-05T07:12:03.120+0000".
std::string audit_time_text(std::int64_t unix_ms);

}  // namespace tiltgate
