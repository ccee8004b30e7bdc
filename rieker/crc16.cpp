#include "rieker/crc16.h"

#include "driver/crc16_a001.h"

namespace tiltgate::rieker {

// CRC-16/ARC: initial value 0x0000, no final xor (docs/protocols.md, "Rieker CRC16").
std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  return crc16_a001::compute(0x0000, bytes);
}

}  // namespace tiltgate::rieker
