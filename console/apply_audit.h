// The audit records of a configuration applied through the console and of its confirmation
// window (console/confirm_window.h): one place, each through the console's audit call
// (console/console_audit.h) with what changed as its text.
#pragma once

#include <fmt/format.h>

#include <string>

#include "console/console_audit.h"
#include "console/pending_apply.h"

namespace tiltgate {

inline void record_apply(AuditTrail* audit, const std::string& user, const std::string& changes,
                         std::string result) {
  record_console_change(audit, user, "", "config", "", changes, std::move(result));
}

// An attempt at the configuration refused before anything was tried (the role, a body that is
// not a configuration text): `setting` "config" for an apply, "config confirm" for a confirm.
inline void record_config_refused(AuditTrail* audit, const std::string& user,
                                  std::string setting, const std::string& why) {
  record_console_change(audit, user, "", std::move(setting), "", "", "refused: " + why);
}

inline void record_confirmed(AuditTrail* audit, const std::string& user,
                             const PendingApply& pending) {
  record_console_change(audit, user, "", "config confirm", "", pending.changes,
                        fmt::format("ok: applied by {}, confirmed", pending.user));
}

inline void record_rolled_back(AuditTrail* audit, const PendingApply& pending,
                               const std::string& result) {
  record_console_change(audit, pending.user, "", "config rollback", pending.changes,
                        "the previous file", result);
}

}  // namespace tiltgate
