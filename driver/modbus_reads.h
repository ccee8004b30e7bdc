// Which Modbus requests only read a device: a fact of the Modbus Application Protocol that the
// Modbus TCP server (writes refused, pass-through audited) and the Modbus families (a command's
// raw request on a gateway's line audited, driver/carried_request.h) both need. Pure.
#pragma once

#include <cstdint>
#include <span>

namespace tiltgate {

// Whether a request PDU only reads, so that it may pass through while [server] writes is
// false, and come from a host outside [server] write_allow: 01, 02, 03, 04 (reads), 07 (read
// exception status), 08 with sub-function 0000, 0002 or 000B..0012 (return query data, the
// diagnostic register, the counts), 0B and 0C (communication event counter and log), 11
// (report server id), 14 (read file record), 18 (read FIFO queue) and 2B/0E (read device
// identification). Everything else may change the device (08's other sub-functions restart it,
// clear its counters or silence it) and is refused with 0x01.
bool reads_only(std::span<const std::uint8_t> pdu);

}  // namespace tiltgate
