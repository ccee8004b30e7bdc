// Each audit record as a structured entry of the systemd journal (docs/operations.md, "The
// audit trail in the journal"): the record's fields as journal fields of their own, so a site
// ships them to a remote log server (systemd-journal-upload, rsyslog's imjournal) and can
// compare the trail with what left the machine. The entry's MESSAGE is the line the log shows
// ("audit: door modbus, who ...: ack").
#pragma once

#include <string>
#include <vector>

#include "audit/audit_record.h"

namespace tiltgate {

// The entry's fields, "NAME=value" each: MESSAGE, PRIORITY (6, or 4 for a refusal or an error),
// SYSLOG_IDENTIFIER, MESSAGE_ID (kAuditMessageId, the same for every audit record) and
// TILTGATE_AUDIT_TIME_MS, _DOOR, _WHO, _SENSOR, _SETTING, _OLD (when known), _NEW, _RESULT and
// _HASH (the record's link in the chain, audit/audit_chain.h). The record's text is already
// visible_text's (the trail's record() made it so): no field holds a newline.
std::vector<std::string> audit_journal_fields(const AuditRecord& record, const std::string& hash);

// journalctl MESSAGE_ID=... finds every audit record of every tiltgate.
inline constexpr const char* kAuditMessageId = "6b1c4d0e2f8a4c55a7b3e9d21f0c8a47";

// Sends the entry to the journal (sd_journal_sendv); a failure is logged once.
void send_audit_to_journal(const AuditRecord& record, const std::string& hash);

}  // namespace tiltgate
