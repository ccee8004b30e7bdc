#include "mapping/value_codec.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace tiltgate {
namespace {

std::uint16_t byte_swapped(std::uint16_t word) { return std::uint16_t((word << 8) | (word >> 8)); }

double rounded(double value, Rounding rounding) {
  switch (rounding) {
    case Rounding::nearest:
      return std::round(value);  // halves away from zero
    case Rounding::floor:
      return std::floor(value);
    case Rounding::ceil:
      return std::ceil(value);
    case Rounding::truncate:
      return std::trunc(value);
  }
  return std::round(value);
}

}  // namespace

void put_bits(std::span<std::uint16_t> out, std::uint64_t value, RegisterOrder order) {
  const std::size_t n = out.size();
  for (std::size_t i = 0; i < n; ++i) {
    // Word i of the big-endian layout; a word swap reverses the words.
    auto word = std::uint16_t(value >> (16 * (n - 1 - i)));
    if (swaps_bytes(order)) word = byte_swapped(word);
    out[swaps_words(order) ? n - 1 - i : i] = word;
  }
}

std::uint64_t get_bits(std::span<const std::uint16_t> in, RegisterOrder order) {
  const std::size_t n = in.size();
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < n; ++i) {
    auto word = in[swaps_words(order) ? n - 1 - i : i];
    if (swaps_bytes(order)) word = byte_swapped(word);
    value = (value << 16) | word;
  }
  return value;
}

std::int64_t to_integer(double value, Rounding rounding, std::int64_t min, std::int64_t max,
                        double nan_value) {
  if (std::isnan(value)) value = nan_value;
  if (std::isnan(value)) return 0;
  const double r = rounded(value, rounding);
  // Compare as doubles first: casting an out-of-range double to an integer is undefined.
  if (r <= double(min)) return min;
  if (r >= double(max)) return max;
  return std::int64_t(r);
}

bool integer_limits(PointType type, std::int64_t& min, std::int64_t& max) {
  switch (type) {
    case PointType::boolean:
      min = 0, max = 1;
      return true;
    case PointType::uint16:
      min = 0, max = 65535;
      return true;
    case PointType::int16:
      min = -32768, max = 32767;
      return true;
    case PointType::uint32:
      min = 0, max = std::numeric_limits<std::uint32_t>::max();
      return true;
    case PointType::int32:
      min = std::numeric_limits<std::int32_t>::min();
      max = std::numeric_limits<std::int32_t>::max();
      return true;
    default:
      return false;
  }
}

void encode_number(std::span<std::uint16_t> out, PointType type, double value, RegisterOrder order,
                   Rounding rounding, double nan_value) {
  std::int64_t min = 0, max = 0;
  if (integer_limits(type, min, max)) {
    const std::int64_t n = to_integer(value, rounding, min, max, nan_value);
    // Two's complement in the point's width: put_bits keeps the low 16 * words bits.
    put_bits(out, std::uint64_t(n), order);
  } else if (type == PointType::float32) {
    put_bits(out, std::bit_cast<std::uint32_t>(float(value)), order);
  } else if (type == PointType::float64) {
    put_bits(out, std::bit_cast<std::uint64_t>(value), order);
  }
}

double decode_number(std::span<const std::uint16_t> in, PointType type, RegisterOrder order) {
  const std::uint64_t bits = get_bits(in, order);
  switch (type) {
    case PointType::int16:
      return std::int16_t(std::uint16_t(bits));
    case PointType::int32:
      return std::int32_t(std::uint32_t(bits));
    case PointType::float32:
      return std::bit_cast<float>(std::uint32_t(bits));
    case PointType::float64:
      return std::bit_cast<double>(bits);
    default:
      return double(bits);
  }
}

void put_uint32(std::span<std::uint16_t, 2> out, std::uint32_t value, WordOrder order) {
  put_bits(out, value, register_order(order));
}

std::uint32_t get_uint32(std::span<const std::uint16_t, 2> in, WordOrder order) {
  return std::uint32_t(get_bits(in, register_order(order)));
}

void put_float32(std::span<std::uint16_t, 2> out, float value, WordOrder order) {
  put_bits(out, std::bit_cast<std::uint32_t>(value), register_order(order));
}

float get_float32(std::span<const std::uint16_t, 2> in, WordOrder order) {
  return std::bit_cast<float>(std::uint32_t(get_bits(in, register_order(order))));
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
  return std::int16_t(to_integer(value * scale, Rounding::nearest, -32768, 32767, 0));
}

std::uint16_t saturate_uint16(double value) {
  return std::uint16_t(to_integer(value, Rounding::nearest, 0, 65535, 0));
}

}  // namespace tiltgate
