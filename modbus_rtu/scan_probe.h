// How `tiltgate scan` finds Modbus RTU devices (driver/scan.h): a read of the device profile's
// first [[read]] block when the scan was given a profile, else Report Server ID (FC 17), which
// needs no register map. Any reply from the slave asked, an exception included, shows a device
// at that address: a device that does not implement FC 17 answers "illegal function".
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "driver/scan.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/device_profile.h"
#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

boost::asio::awaitable<ProbeResult> device_probe(Line& line, const ProbeSetup& setup);

// The probe for `slave`: the block's read, or FC 17 without one. Pure.
Expected<Request, CodecError> probe_request(std::uint8_t slave,
                                            const std::optional<ReadBlock>& first_block);

// A probe and its reply on the wire at `baud` (11 bits a character), with 5 ms for the device
// to answer: the serial line spec leaves its turnaround to the device.
std::chrono::microseconds probe_time(std::uint32_t baud);

// What one probe found, from its framer after the Line's exchange: a reply from the slave
// (registers or an exception), bytes that failed their CRC (two devices at one address), or
// nothing. Pure, for tests.
ProbeResult probe_outcome(const RtuReplyFramer& framer, std::uint32_t address);

}  // namespace tiltgate::modbus_rtu
