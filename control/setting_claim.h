// Whether the gateway believes a command's `setting` report (control/control_protocol.h): the
// command keeps the framer, so only it knows what its transactions meant, but the gateway knows
// which it carried and how each ended. A report is taken only right after a transaction of the
// same session that ended as the report says (answered for "ack" or "nak", timed out for
// "timeout"), once: a report with no transaction behind it would record, and show, a change
// the gateway never sent (issue 52, item 3). One decision, pure.
#pragma once

#include <optional>
#include <string>

#include "control/control_protocol.h"

namespace tiltgate::control {

// How the session's latest transaction since its last report ended.
enum class CarriedOutcome {
  none,       // none since the last report (or since the session began)
  answered,   // the line carried it and the framer took a reply (or none was expected)
  timed_out,  // the line carried it and no reply came
  not_sent,   // it failed before the device was asked, or the bus did not get to it
};

CarriedOutcome carried_outcome(const Ended& ended);

// A setting's outcome as the audit trail words it (audit/audit_record.h): "ack", "nak 0x03",
// "timeout".
std::string setting_result(const SettingChanged& changed);

// None: the report may be taken. Otherwise why not, for the refusal and the audit trail.
std::optional<std::string> setting_claim_refusal(CarriedOutcome carried,
                                                 const SettingChanged& claim);

}  // namespace tiltgate::control
