// GET /api/audit (docs/web-console.md, "The API"): the trail's newest records, filtered by the
// query's door, sensor, who and setting, at most its limit (1..10000). Each record with its
// time twice: Unix ms, and as UTC text for a person.
#pragma once

#include <string_view>

#include "audit/audit_trail.h"
#include "http/http_routes.h"

namespace tiltgate {

// No trail (a gateway tested without one): an empty list.
HttpReply audit_reply(const AuditTrail* trail, std::string_view target);

}  // namespace tiltgate
