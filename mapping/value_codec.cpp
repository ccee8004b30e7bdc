#include "mapping/value_codec.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace tiltgate {

void put_uint32(std::span<std::uint16_t, 2> out, std::uint32_t value, WordOrder order) {
  const auto high = std::uint16_t(value >> 16);
  const auto low = std::uint16_t(value & 0xFFFF);
  out[0] = order == WordOrder::big ? high : low;
  out[1] = order == WordOrder::big ? low : high;
}

std::uint32_t get_uint32(std::span<const std::uint16_t, 2> in, WordOrder order) {
  const std::uint32_t high = order == WordOrder::big ? in[0] : in[1];
  const std::uint32_t low = order == WordOrder::big ? in[1] : in[0];
  return (high << 16) | low;
}

void put_float32(std::span<std::uint16_t, 2> out, float value, WordOrder order) {
  put_uint32(out, std::bit_cast<std::uint32_t>(value), order);
}

float get_float32(std::span<const std::uint16_t, 2> in, WordOrder order) {
  return std::bit_cast<float>(get_uint32(in, order));
}

void put_string(std::span<std::uint16_t> out, std::string_view text) {
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto at = [&](std::size_t k) -> std::uint8_t {
      return k < text.size() ? std::uint8_t(text[k]) : std::uint8_t(' ');
    };
    out[i] = std::uint16_t((at(2 * i) << 8) | at(2 * i + 1));
  }
}

std::int16_t saturate_int16(double value, double scale) {
  if (std::isnan(value)) return 0;
  const double scaled = std::round(value * scale);
  return std::int16_t(std::clamp(scaled, double(std::numeric_limits<std::int16_t>::min()),
                                 double(std::numeric_limits<std::int16_t>::max())));
}

std::uint16_t saturate_uint16(double value) {
  if (std::isnan(value)) return 0;
  return std::uint16_t(std::clamp(std::round(value), 0.0, 65535.0));
}

}  // namespace tiltgate
