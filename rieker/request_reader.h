// What a Rieker request on a gateway's line asks of a sensor, and whether a reply refuses it,
// read from the frames' bytes (driver/carried_request.h): the control socket records every
// request a command sends that may change a sensor. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/carried_request.h"

namespace tiltgate::rieker {

// The Get functions and Check Address read; Change Lock only opens the changes after it (each
// of which is recorded); every other function, the factory's reserved ones included, may change
// the sensor. None for bytes that are not one frame with a good CRC.
std::optional<CarriedRequest> read_request(std::span<const std::uint8_t> request);
// "nak 0x04" for a NAK frame; none for anything else.
std::optional<std::string> read_refusal(std::span<const std::uint8_t> reply);
// A reply's values as the request asked for them: angles, an address, the firmware, the lock
// level, the serial, or "ack"; none for a NAK or a frame that does not answer the request.
std::optional<std::string> read_reply(std::span<const std::uint8_t> request,
                                      std::span<const std::uint8_t> reply);

}  // namespace tiltgate::rieker
