// Values <-> 16-bit registers: register and byte order, integers with rounding and
// saturation, floats, strings. Pure functions, shared by reads, writes and the map export.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "mapping/point_types.h"

namespace tiltgate {

// The bits of `value` (the low 16 * out.size() bits, most significant first) laid out in
// out.size() registers (1, 2 or 4) in `order`; get_bits reads them back.
void put_bits(std::span<std::uint16_t> out, std::uint64_t value, RegisterOrder order);
std::uint64_t get_bits(std::span<const std::uint16_t> in, RegisterOrder order);

// The integer a scaled value becomes: rounded as asked, then clamped to min..max (never
// wrapped); NaN gives nan_value, clamped the same way.
std::int64_t to_integer(double value, Rounding rounding, std::int64_t min, std::int64_t max,
                        double nan_value);

// A numeric register type's value range (bool: 0..1). Floats and strings: none (false).
bool integer_limits(PointType type, std::int64_t& min, std::int64_t& max);

// A scaled value into out (the point's words) as `type` in `order`. Integer types round and
// saturate; floats keep NaN.
void encode_number(std::span<std::uint16_t> out, PointType type, double value, RegisterOrder order,
                   Rounding rounding, double nan_value);
// The number the registers hold, as `type` in `order` (before any scale is undone).
double decode_number(std::span<const std::uint16_t> in, PointType type, RegisterOrder order);

// Shorthands in the [server] word order.
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
