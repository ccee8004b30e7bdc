#include "modbus_rtu/crc.h"

#include "driver/crc16_a001.h"

namespace tiltgate::modbus_rtu {

std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte) {
  return crc16_a001::update(crc, byte);
}

std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  return crc16_a001::compute(kCrcInitial, bytes);
}

void append_crc(std::vector<std::uint8_t>& frame) {
  const std::uint16_t crc = crc16(frame);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
}

bool crc_ok(std::span<const std::uint8_t> frame) {
  if (frame.size() < 4) return false;
  const std::uint16_t crc = crc16(frame.first(frame.size() - 2));
  return frame[frame.size() - 2] == (crc & 0xFF) && frame[frame.size() - 1] == (crc >> 8);
}

}  // namespace tiltgate::modbus_rtu
