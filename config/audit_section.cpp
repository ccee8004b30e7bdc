// [audit]: what the audit trail does when its disk refuses records (docs/configuration.md,
// "[audit]"; docs/operations.md, "A disk that refuses the trail").
#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

AuditConfig read_audit(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "audit", errors);
  AuditConfig audit;
  if (auto when_full = in.choice("when_full", {"keep", "refuse"}))
    audit.when_full = *when_full == "refuse" ? AuditConfig::WhenFull::refuse
                                             : AuditConfig::WhenFull::keep;
  // At least a few records; at most half the trail's 4 MiB on disk, so the records held never
  // push the trail's own older records off the disk (audit/audit_trail.h).
  if (auto kib = in.integer("memory_kib", 16, 2048)) audit.memory_kib = *kib;
  in.reject_unknown_keys();
  return audit;
}

}  // namespace tiltgate::config
