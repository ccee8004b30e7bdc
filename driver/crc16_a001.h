// The table-driven CRC-16 over the reflected polynomial 0x8005 (0xA001), which two families'
// checksums share: CRC-16/ARC (initial value 0x0000) and CRC-16/MODBUS (initial value
// 0xFFFF). Each family's codec fixes its own initial value and byte order on the wire.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace tiltgate::crc16_a001 {

inline constexpr std::uint16_t kReflectedPolynomial = 0xA001;  // 0x8005 bit-reversed

inline constexpr std::array<std::uint16_t, 256> kTable = [] {
  std::array<std::uint16_t, 256> table{};
  for (unsigned byte = 0; byte < 256; ++byte) {
    auto crc = static_cast<std::uint16_t>(byte);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1u) ? static_cast<std::uint16_t>((crc >> 1) ^ kReflectedPolynomial)
                       : static_cast<std::uint16_t>(crc >> 1);
    }
    table[byte] = crc;
  }
  return table;
}();

inline std::uint16_t update(std::uint16_t crc, std::uint8_t byte) {
  return static_cast<std::uint16_t>((crc >> 8) ^ kTable[(crc ^ byte) & 0xFFu]);
}

inline std::uint16_t compute(std::uint16_t initial, std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = initial;
  for (std::uint8_t b : bytes) crc = update(crc, b);
  return crc;
}

}  // namespace tiltgate::crc16_a001
