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

// Whether the trail reaches its disk, and what it lost when it could not (docs/operations.md,
// "A disk that refuses the trail"): /metrics' tiltgate_audit_records_held,
// tiltgate_audit_records_lost_total and tiltgate_audit_disk_refuses.
struct AuditHealth {
  std::uint64_t held = 0;  // records the disk refused, kept in memory to be written later
  std::uint64_t lost = 0;  // since start: past the memory budget while the disk refused
  bool disk_refuses = false;

  bool operator==(const AuditHealth&) const = default;
};

// The class of an AuditRecord's result: its first word ("nak 0x03" -> "nak", "refused: a
// role" -> "refused"); "error" for a result none of the classes names.
std::string_view audit_result_class(std::string_view result);

}  // namespace tiltgate
