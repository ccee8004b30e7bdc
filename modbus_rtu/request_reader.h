// What a Modbus request on a gateway's line asks of a device, and whether a reply refuses it,
// on either Modbus protocol: an RTU frame or an MBAP frame (driver/carried_request.h). The
// control socket records every request a command sends that may change a device. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/carried_request.h"

namespace tiltgate::modbus_rtu {

// Reads as driver/modbus_reads.h says; every other function, a device profile's own included,
// may change the device. None for bytes that are not one RTU frame with a good CRC.
std::optional<CarriedRequest> read_rtu_request(std::span<const std::uint8_t> request);
// "nak 0x02" for an exception reply (function code with bit 7 set); none for anything else.
std::optional<std::string> read_rtu_refusal(std::span<const std::uint8_t> reply);
// The same for a device that speaks Modbus TCP: one MBAP frame.
std::optional<CarriedRequest> read_mbap_request(std::span<const std::uint8_t> request);
std::optional<std::string> read_mbap_refusal(std::span<const std::uint8_t> reply);
// A reply's values as the request asked for them: the registers read ("values 4, 1"), the
// coils or inputs ("bits 1 0 1"), "written" for a write echoed, "echo" for a diagnostic; none
// for an exception or a frame that does not answer the request.
std::optional<std::string> read_rtu_reply(std::span<const std::uint8_t> request,
                                          std::span<const std::uint8_t> reply);
std::optional<std::string> read_mbap_reply(std::span<const std::uint8_t> request,
                                           std::span<const std::uint8_t> reply);

}  // namespace tiltgate::modbus_rtu
