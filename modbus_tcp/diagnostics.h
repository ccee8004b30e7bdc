// Modbus functions 08 (Diagnostics) and 11 (Get Comm Event Counter) on the gateway's units:
// which sub-functions it serves, how a request is checked, and the reply's bytes. Pure.
// What each count is for a sensor behind the gateway is gateway/unit_diagnostics.h's; the
// manual's page is docs/diagnostics.md.
//
// Reference: "Modbus Application Protocol Specification V1.1b3", sections 6.8 (08) and 6.9 (11).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

namespace diagnostic {
inline constexpr std::uint16_t return_query_data = 0x0000;
inline constexpr std::uint16_t clear_counters = 0x000A;
inline constexpr std::uint16_t bus_message_count = 0x000B;
inline constexpr std::uint16_t bus_communication_error_count = 0x000C;
inline constexpr std::uint16_t bus_exception_error_count = 0x000D;
inline constexpr std::uint16_t server_message_count = 0x000E;
inline constexpr std::uint16_t server_no_response_count = 0x000F;
inline constexpr std::uint16_t server_nak_count = 0x0010;
inline constexpr std::uint16_t server_busy_count = 0x0011;
inline constexpr std::uint16_t bus_character_overrun_count = 0x0012;
}  // namespace diagnostic

// 0x000B..0x0012: a sub-function that returns one count.
inline bool returns_count(std::uint16_t sub_function) {
  return sub_function >= diagnostic::bus_message_count &&
         sub_function <= diagnostic::bus_character_overrun_count;
}

// 08's PDU (function, sub-function, data) into `request` (its `diagnostic` and `is_write`):
// 0x0000 takes any data, echoed; 0x000A and the counts take the data 0x0000 and nothing else
// (03 otherwise, as the section's tables give it); any other sub-function is one the gateway
// does not serve (01). 0x000A changes the unit's counters: a write, under the write rules.
std::optional<ModbusException> check_diagnostics(std::span<const std::uint8_t> pdu,
                                                 ModbusRequest& request);
// 11's PDU is the function code alone (03 otherwise).
std::optional<ModbusException> check_comm_event_counter(std::span<const std::uint8_t> pdu);

// The reply PDU's data after its function code: for 08, the request's sub-function and data
// echoed (0x0000, 0x000A) or the sub-function and `values[0]` (the counts); for 11, the status
// word and the event count, `values[0]` and `values[1]`. Empty when `values` is too short.
std::vector<std::uint8_t> diagnostics_reply_data(const ModbusRequest& request,
                                                 std::span<const std::uint16_t> values);

}  // namespace tiltgate
