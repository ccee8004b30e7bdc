// Modbus RTU frames as a listener that only hears the line cuts them
// (driver/passive_framing.h): a frame's length follows from its function code, as the master
// or the slave would read it (modbus_rtu/frame_length.h, libmodbus' rule), and its CRC
// confirms it; a function code the rule does not know ends where its CRC matches. A reply
// comes from the slave the request addressed, with the request's function code or its
// exception, so the next request after an unanswered one is not taken for the reply; a
// broadcast (slave 0) gets none (Serial Line 2.2). Pure.
#pragma once

#include <cstdint>
#include <span>

#include "driver/passive_framing.h"

namespace tiltgate::modbus_rtu {

PassiveCut passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                         std::span<const std::uint8_t> request);

}  // namespace tiltgate::modbus_rtu
