// How `tiltgate scan` finds Modbus RTU devices (driver/scan.h): a read of the device profile's
// first [[read]] block when the scan was given a profile, else Report Server ID (FC 17), which
// needs no register map. Any reply from the slave asked, an exception included, shows a device
// at that address: a device that does not implement FC 17 answers "illegal function".
//
// Over Modbus TCP (protocol "modbus-tcp") the same probe goes in an MBAP frame to each unit id.
// A Modbus TCP device that is a gateway to others answers for a unit id it cannot reach with
// exception 0x0B (gateway target device failed to respond) or 0x0A (gateway path unavailable,
// a unit id it has no route for): nobody is there.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "driver/scan.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/device_profile.h"
#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

boost::asio::awaitable<ProbeResult> device_probe(Line& line, const ProbeSetup& setup);
// The same over MBAP: unit ids 0..255.
boost::asio::awaitable<ProbeResult> mbap_device_probe(Line& line, const ProbeSetup& setup);

// The probe for `slave`: the block's read, or FC 17 without one. Pure.
Expected<Request, CodecError> probe_request(std::uint8_t slave,
                                            const std::optional<ReadBlock>& first_block);

// A probe and its reply on the wire at `baud` (11 bits a character), with 5 ms for the device
// to answer: the serial line spec leaves its turnaround to the device.
std::chrono::microseconds probe_time(std::uint32_t baud);
// Over Modbus TCP no wire time: 20 ms for the device (or the gateway it is) to answer; the
// connection's round trip is the Line's to add.
std::chrono::microseconds mbap_probe_time(std::uint32_t baud);

// What one probe found, from its framer after the Line's exchange: a reply from the slave
// (registers or an exception), bytes that failed their CRC (two devices at one address), or
// nothing. Pure, for tests.
// Over MBAP (`adu`), a gateway's 0x0A or 0x0B is silence.
ProbeResult probe_outcome(const ModbusReplyFramer& framer, std::uint32_t address,
                          Adu adu = Adu::rtu);

}  // namespace tiltgate::modbus_rtu
