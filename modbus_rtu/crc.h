// CRC-16/MODBUS (Modbus over Serial Line V1.02, 6.2.2): polynomial 0x8005 processed reflected
// (0xA001), initial value 0xFFFF, no final xor. It covers the slave address through the last
// data byte and is sent low byte first, unlike every other Modbus field.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace tiltgate::modbus_rtu {

inline constexpr std::uint16_t kCrcInitial = 0xFFFF;

std::uint16_t crc16(std::span<const std::uint8_t> bytes);
// One more byte into a running CRC (start from kCrcInitial). The CRC of a frame with its own
// CRC appended, low byte first, is 0: a parser can keep one running CRC per candidate start.
std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte);

// Appends the CRC of everything in `frame`, low byte first.
void append_crc(std::vector<std::uint8_t>& frame);

// A frame of at least 4 bytes (address, function, CRC) whose last two bytes are the CRC of the
// rest, low byte first.
bool crc_ok(std::span<const std::uint8_t> frame);

}  // namespace tiltgate::modbus_rtu
