#include "app/audit_command.h"

#include <algorithm>
#include <deque>
#include <filesystem>
#include <fmt/format.h>
#include <memory>

#include "audit/audit_json.h"
#include "audit/audit_text.h"
#include "audit/audit_trail.h"
#include "config/config.h"

namespace tiltgate {

namespace {

struct AuditCommandOptions {
  std::string state_dir = std::string(kDefaultStateDir);
  AuditTrail::Filter filter;
  bool json = false;
  bool verify = false;
};

// --verify: exit 0 when the chain holds, 1 with the first record edited, removed or reordered
// named (docs/operations.md, "Tamper evidence").
int verify_command(const std::string& folder) {
  auto check = verify_audit_folder(folder);
  if (!check) {
    fmt::print(stderr, "cannot read the audit trail: {}\n", check.error());
    return 1;
  }
  if (check->broken_at) {
    fmt::print("the audit trail was changed after it was written: {}\n", check->problem);
    return 1;
  }
  fmt::print("the audit trail's chain holds: {} records", check->records);
  if (check->unchained > 0)
    fmt::print(" (the first {} written before the trail was chained, not verifiable)",
               check->unchained);
  fmt::print("\n");
  if (!check->last_hash.empty())
    fmt::print("the newest record's hash: {} (the journal's last TILTGATE_AUDIT_HASH should be "
               "the same: records removed from the end show only there)\n",
               check->last_hash);
  return 0;
}

int audit_command(const AuditCommandOptions& options) {
  const std::string folder = audit_folder(options.state_dir);
  if (!std::filesystem::is_directory(folder)) {
    fmt::print(stderr, "no audit trail in {} (is [server] state_dir {}?)\n", folder,
               options.state_dir);
    return 1;
  }
  if (options.verify) return verify_command(folder);
  auto records = read_audit_folder(folder);
  if (!records) {
    fmt::print(stderr, "cannot read the audit trail: {}\n", records.error());
    return 1;
  }
  const std::deque<AuditRecord> all(records->begin(), records->end());
  std::vector<AuditRecord> selected = select_audit(all, options.filter);  // newest first
  if (options.json) {
    fmt::print("{}\n", audit_json(selected));
    return 0;
  }
  // Oldest first, as a log reads: the newest at the bottom.
  std::reverse(selected.begin(), selected.end());
  for (const AuditRecord& record : selected)
    fmt::print("{}  {}\n", audit_time_text(record.unix_ms), audit_text(record));
  return 0;
}

}  // namespace

Subcommand add_audit(CLI::App& app) {
  auto options = std::make_shared<AuditCommandOptions>();
  options->filter.limit = 100;
  CLI::App* audit = app.add_subcommand(
      "audit", "print the audit trail: every change to a sensor, by whom, through which door");
  audit->add_option("--state-dir", options->state_dir, "the gateway's [server] state_dir")
      ->capture_default_str();
  audit->add_option("--sensor", options->filter.sensor, "only this sensor, as \"bus/sensor\"");
  audit->add_option("--door", options->filter.door,
                    "only this door: modbus, sparkplug, \"control socket\", console, gateway "
                    "(its own notices: records lost)");
  audit->add_option("--who", options->filter.who, "only records whose who contains this");
  audit->add_option("--setting", options->filter.setting, "only this setting");
  audit->add_option("--limit", options->filter.limit, "the newest this many; 0: all")
      ->capture_default_str();
  audit->add_flag("--json", options->json, "JSON, newest first, as GET /api/audit answers");
  audit->add_flag("--verify", options->verify,
                  "check the chain of hashes over every record: exit 1 naming the first record "
                  "edited, removed or reordered");
  return {audit, [options] { return audit_command(*options); }};
}

}  // namespace tiltgate
