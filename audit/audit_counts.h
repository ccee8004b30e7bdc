// How many changes the audit trail recorded since the gateway started, by door and by the
// class of their result: what /metrics counts (tiltgate_audit_records_total). Plain data.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

struct AuditCount {
  std::string door;
  std::string result;  // a class: ack, nak, timeout, refused, error, ok
  std::uint64_t records = 0;

  bool operator==(const AuditCount&) const = default;
};

// By door, then by result class.
using AuditCounts = std::vector<AuditCount>;

// The class of an AuditRecord's result: its first word ("nak 0x03" -> "nak", "refused: a
// role" -> "refused"); "error" for a result none of the classes names.
std::string_view audit_result_class(std::string_view result);

}  // namespace tiltgate
