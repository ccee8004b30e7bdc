// Modbus RTU test helpers: frames written as hex, and an independent bit-by-bit CRC-16/MODBUS
// (the spec's own algorithm, Serial Line 6.2.2) to check the table-driven one against.
#pragma once

#include <cctype>
#include <cstdint>
#include <string_view>
#include <vector>

namespace tiltgate::modbus_rtu::test {

// "01 03 00 00" -> bytes; spaces are ignored.
inline std::vector<std::uint8_t> hex(std::string_view text) {
  std::vector<std::uint8_t> bytes;
  int high = -1;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    const int nibble = std::isdigit(static_cast<unsigned char>(c))
                           ? c - '0'
                           : std::toupper(static_cast<unsigned char>(c)) - 'A' + 10;
    if (high < 0) {
      high = nibble;
    } else {
      bytes.push_back(static_cast<std::uint8_t>(high * 16 + nibble));
      high = -1;
    }
  }
  return bytes;
}

// Serial Line 6.2.2, step by step: xor each byte into the low byte, then 8 shifts, xoring
// 0xA001 after each shift that drops a 1.
inline std::uint16_t reference_crc(const std::vector<std::uint8_t>& bytes) {
  std::uint16_t crc = 0xFFFF;
  for (std::uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i) {
      const bool lsb = crc & 1u;
      crc = static_cast<std::uint16_t>(crc >> 1);
      if (lsb) crc ^= 0xA001;
    }
  }
  return crc;
}

// `body` with its CRC appended low byte first, computed by reference_crc.
inline std::vector<std::uint8_t> framed(std::string_view body) {
  std::vector<std::uint8_t> frame = hex(body);
  const std::uint16_t crc = reference_crc(frame);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  return frame;
}

}  // namespace tiltgate::modbus_rtu::test
