// The Rieker Flex CRC16 (H6/H4360 manual, "CRC16"): polynomial x^16 + x^15 + x^2 + 1, initial
// value 0x0000. The manual's check values reproduce only with the polynomial processed
// reflected (0xA001) and no final xor, i.e. CRC-16/ARC. It covers DEST through DATA and is
// sent high byte first.
#pragma once

#include <cstdint>
#include <span>

namespace tiltgate::rieker {

std::uint16_t crc16(std::span<const std::uint8_t> bytes);

}  // namespace tiltgate::rieker
