// Values <-> 16-bit registers: word order for 32-bit values, strings, saturating integers.
// Pure functions, shared by reads, writes and the map export.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "config/config.h"

namespace tiltgate {

void put_uint32(std::span<std::uint16_t, 2> out, std::uint32_t value, WordOrder order);
std::uint32_t get_uint32(std::span<const std::uint16_t, 2> in, WordOrder order);
void put_float32(std::span<std::uint16_t, 2> out, float value, WordOrder order);
float get_float32(std::span<const std::uint16_t, 2> in, WordOrder order);

// Two characters per register, first in the high byte, padded with spaces to out.size()*2
// characters (and truncated if longer).
void put_string(std::span<std::uint16_t> out, std::string_view text);

// round(value * scale) clamped to the int16 range; NaN gives 0.
std::int16_t saturate_int16(double value, double scale);
// Clamps to 0..65535.
std::uint16_t saturate_uint16(double value);

}  // namespace tiltgate
