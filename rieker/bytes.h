// Big-endian field access for Rieker frames: every multi-byte field on the wire is sent high
// byte first (manual, "Packet Format"); angles are IEEE-754 float32.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

namespace tiltgate::rieker {

inline void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

inline void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  put_u16(out, static_cast<std::uint16_t>(v >> 16));
  put_u16(out, static_cast<std::uint16_t>(v));
}

inline void put_f32(std::vector<std::uint8_t>& out, float v) {
  put_u32(out, std::bit_cast<std::uint32_t>(v));
}

inline std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

inline std::uint32_t get_u32(const std::uint8_t* p) {
  return (std::uint32_t{get_u16(p)} << 16) | get_u16(p + 2);
}

inline float get_f32(const std::uint8_t* p) { return std::bit_cast<float>(get_u32(p)); }

}  // namespace tiltgate::rieker
