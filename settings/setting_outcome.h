// What came of a change of one sensor setting, as every door answers it (the console's
// POST /api/sensors/NAME/settings, a Sparkplug DCMD) and the audit trail records it
// (audit/audit_record.h's result): the sensor's ACK, its NAK (with its code when it sent one),
// no answer in time, or refused before anything was sent. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "driver/sensor_driver.h"

namespace tiltgate {

struct SettingOutcome {
  enum class Result { ack, nak, timeout, refused } result = Result::refused;
  std::string detail;               // for people: the NAK's code, why refused...
  std::optional<double> old_value;  // the sensor's setting before, when known
  std::optional<std::uint8_t> code;  // nak: the sensor's refusal code, when it sent one
};

// A failed write as the sensor's bus answered it (driver/sensor_driver.h WriteError):
//   no answer (a time-out, a port failure, the sensor known offline, the gateway stopping) and
//     a write the busy bus could not start before its deadline: timeout;
//   a NAK or a Modbus exception (code kept), a NAK of bad data or busy, and any reply that was
//     not the acknowledgement (all a protocol without NAKs can refuse with): nak;
//   a value or setting the driver refused before sending (a range, a setting the model does
//     not have): refused.
// The refusals found before the write is queued (another device at the address, a taken
// address) are the writer's (setting_writer.h), which checks them first.
SettingOutcome outcome_of(const WriteError& error);

// The audit record's result (audit/audit_record.h): "ack", "nak 0x03" ("nak" without a code),
// "timeout", "refused: WHY".
std::string audit_result(const SettingOutcome& outcome);

}  // namespace tiltgate
