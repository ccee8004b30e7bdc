// `tiltgate audit --verify`'s reading of a trail's folder (audit/audit_trail.h,
// verify_audit_folder): the records as stored, each named by its segment file and place, the
// chain checked over them (audit/audit_chain.h), and the first damaged frame named too.
#include <fmt/format.h>

#include "audit/audit_chain.h"
#include "audit/audit_trail.h"
#include "store/record_reader.h"

namespace tiltgate {

Expected<AuditChainCheck, std::string> verify_audit_folder(const std::string& folder) {
  auto segments = store::read_segments(folder);
  if (!segments) return Unexpected(segments.error());
  std::vector<StoredAuditRecord> records;
  std::optional<std::string> damage;
  for (const store::SegmentRecords& segment : *segments) {
    std::size_t index = 0;
    for (const store::Record& record : segment.records) {
      ++index;
      if (record.topic != "audit") continue;
      records.push_back({std::string(record.payload.begin(), record.payload.end()),
                         fmt::format("{}, record {}", segment.name, index)});
    }
    if (segment.damage) {
      damage = fmt::format("{}, record {} ({}): its frame's length or CRC does not match: it "
                           "was edited or the file was cut; the records after it in that file "
                           "cannot be read",
                           segment.name, index + 1, *segment.damage);
      break;
    }
  }
  const bool from_first = !segments->empty() && segments->front().id == 1;
  AuditChainCheck check = check_audit_chain(records, from_first);
  if (!check.broken_at && damage) {
    check.broken_at = records.size();
    check.problem = *damage;
  }
  return check;
}

}  // namespace tiltgate
