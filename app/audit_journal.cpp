#include "app/audit_journal.h"

#include <atomic>
#include <spdlog/spdlog.h>
#include <sys/uio.h>
#include <systemd/sd-journal.h>

#include "audit/audit_counts.h"
#include "audit/audit_text.h"

namespace tiltgate {

std::vector<std::string> audit_journal_fields(const AuditRecord& record, const std::string& hash) {
  const std::string_view result_class = audit_result_class(record.result);
  const bool warning = result_class == "refused" || result_class == "error";
  std::vector<std::string> fields = {
      "MESSAGE=audit: " + audit_text(record),
      std::string("PRIORITY=") + (warning ? "4" : "6"),
      "SYSLOG_IDENTIFIER=tiltgate",
      std::string("MESSAGE_ID=") + kAuditMessageId,
      "TILTGATE_AUDIT_TIME_MS=" + std::to_string(record.unix_ms),
      "TILTGATE_AUDIT_DOOR=" + record.origin.door,
      "TILTGATE_AUDIT_WHO=" + record.origin.who,
      "TILTGATE_AUDIT_SENSOR=" + record.sensor,
      "TILTGATE_AUDIT_SETTING=" + record.setting};
  if (!record.old_value.empty()) fields.push_back("TILTGATE_AUDIT_OLD=" + record.old_value);
  fields.push_back("TILTGATE_AUDIT_NEW=" + record.new_value);
  fields.push_back("TILTGATE_AUDIT_RESULT=" + record.result);
  fields.push_back("TILTGATE_AUDIT_HASH=" + hash);
  return fields;
}

void send_audit_to_journal(const AuditRecord& record, const std::string& hash) {
  const std::vector<std::string> fields = audit_journal_fields(record, hash);
  std::vector<iovec> parts;
  for (const std::string& field : fields)
    parts.push_back({const_cast<char*>(field.data()), field.size()});
  static std::atomic<bool> failure_logged{false};
  if (const int sent = sd_journal_sendv(parts.data(), int(parts.size()));
      sent < 0 && !failure_logged.exchange(true))
    spdlog::error("audit: the journal did not take an audit record (error {}): the trail on "
                  "disk still has it; said once",
                  -sent);
}

}  // namespace tiltgate
