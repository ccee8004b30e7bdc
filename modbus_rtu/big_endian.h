// Modbus's 16-bit fields are big-endian on the wire: written and read byte by byte, so the
// host's own byte order never matters.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace tiltgate::modbus_rtu {

inline void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

inline std::uint16_t get_u16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1]);
}

}  // namespace tiltgate::modbus_rtu
