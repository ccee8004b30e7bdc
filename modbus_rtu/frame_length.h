// How long a Modbus RTU frame is, told from its first bytes: the rule libmodbus' receiver uses
// (modbus.c, compute_meta_length_after_function and compute_data_length_after_meta). The
// function code fixes the length, or says which byte holds the byte count that does; an
// exception reply is always 5 bytes. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace tiltgate::modbus_rtu {

enum class FrameKind { request, reply };

// For function codes whose frame length the rule does not know (a pass-through of something
// unusual): the frame ends where the CRC of the bytes before it matches.
inline constexpr std::size_t kLengthByCrc = 0;

// The whole frame's length (address and CRC included) of a frame starting with `head`;
// nullopt while more bytes are needed to tell (at most the first 11); kLengthByCrc when the
// function code is not one the rule knows.
std::optional<std::size_t> frame_length(FrameKind kind, std::span<const std::uint8_t> head);

}  // namespace tiltgate::modbus_rtu
