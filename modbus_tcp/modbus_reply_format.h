// Modbus TCP reply ADUs, formatted by the gateway itself: a pure function of a checked request
// (parse_adu) and the handler's response, no I/O, no libmodbus. libmodbus 3.1.6's
// modbus_reply / modbus_reply_exception are the reference: tests/unit/modbus_reply_differential
// _test.cpp checks these bytes against theirs for every function served.
//
// References: "Modbus Messaging on TCP/IP Implementation Guide V1.0b" (MBAP header, section
// 3.1.3) and "Modbus Application Protocol Specification V1.1b3" (responses, section 6;
// exceptions, section 7).
#pragma once

#include <cstdint>
#include <vector>

#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

// Whether `response` answers `request`: a read carries exactly `count` values in the table
// the request reads (registers for 03/04, bits for 01/02); a write's success carries none.
bool response_fits(const ModbusRequest& request, const ModbusResponse& response);

// Replaces `reply` with the reply ADU to `request` carrying `response` (its capacity is kept,
// so a connection reusing one buffer allocates nothing per reply):
// - the handler's exception: function | 0x80 and the code;
// - 01/02: byte count and the bits, least significant first; 03/04: byte count and the
//   registers, high byte first;
// - 05/06: the request echoed; 0F/10: address and quantity;
// - 43/14: the identification objects the request asks for (modbus_tcp/device_identification.h);
// - 08 and 11: the echo or the counts (modbus_tcp/diagnostics.h);
// - a response that does not fit the request (response_fits), or a function the parser does
//   not accept: 04 server device failure.
// Transaction id and unit id come from the request, the protocol id is 0 and the length counts
// the unit id and the PDU.
void format_reply(const ModbusRequest& request, const ModbusResponse& response,
                  std::vector<std::uint8_t>& reply);
std::vector<std::uint8_t> format_reply(const ModbusRequest& request,
                                       const ModbusResponse& response);

}  // namespace tiltgate
