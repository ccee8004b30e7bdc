// What a Dyna request on a gateway's line asks of a module, read from its bytes, on either of
// the Dyna's protocols (driver/carried_request.h): the control socket records every request a
// command sends that may change a module. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/carried_request.h"

namespace tiltgate::spectron {

// The 9-bit protocol: the address byte, then the command line. Reads: read sensor, read
// temperature, firmware revision, read EEPROM; write EEPROM and reset may change the module.
// None for bytes that are not an address byte and a command line ending in CR LF.
std::optional<CarriedRequest> read_nine_bit_request(std::span<const std::uint8_t> request);
// The Modbus-ASCII style protocol: one frame with a good LRC; the same reads and changes.
std::optional<CarriedRequest> read_ascii_request(std::span<const std::uint8_t> request);
// The Dyna has no refusal reply on either protocol (the application note lists none; docs/
// protocols.md, "Dyna: what the gateway does"): always none, a reply is taken as "ack".
std::optional<std::string> read_refusal(std::span<const std::uint8_t> reply);
// A reply's value as the request asked for it: the counts, the temperature's, an EEPROM word,
// the revision, or "ack"; none for a reply that does not answer the request.
std::optional<std::string> read_nine_bit_reply(std::span<const std::uint8_t> request,
                                               std::span<const std::uint8_t> reply);
std::optional<std::string> read_ascii_reply(std::span<const std::uint8_t> request,
                                            std::span<const std::uint8_t> reply);

}  // namespace tiltgate::spectron
