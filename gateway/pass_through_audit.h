// A request passed through to a device ([[bus]] pass_through) that may change it, as the audit
// trail records it (audit/audit_record.h): every function but the reads (modbus_tcp's
// reads_only(): FC 5, 6, 15, 16, 22, 23, a device profile's own write functions, anything
// unknown), from what the gateway itself carried and got back, never from what a client says
// it did. Pure.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "audit/audit_record.h"
#include "line_scheduling/bus_answers.h"

namespace tiltgate {

// sensor "BUS/UNIT" (the device's address); setting "function 06"; new value the request's
// data after the function code in hex ("00000002": FC 6, register 0 := 2); result "ack" for a
// normal reply, "nak 0x02" for the device's exception, "timeout" when it did not answer,
// "error: WHY" when the request was never sent (the bus queue full, not sent before
// write_timeout_ms, the protocol cannot frame it).
AuditRecord pass_through_record(std::string_view bus, std::uint8_t unit_id,
                                std::span<const std::uint8_t> pdu, const ForwardResult& result,
                                WriteOrigin origin);
// One refused before it went to the bus: "refused: WHY".
AuditRecord pass_through_refusal(std::string_view bus, std::uint8_t unit_id,
                                 std::span<const std::uint8_t> pdu, std::string_view why,
                                 WriteOrigin origin);

}  // namespace tiltgate
