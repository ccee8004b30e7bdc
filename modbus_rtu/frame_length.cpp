#include "modbus_rtu/frame_length.h"

#include "modbus_rtu/codec.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::size_t kCrcSize = 2;

// A length given by the byte count at `count_at`: the bytes up to and including it, the
// counted bytes, the CRC.
std::optional<std::size_t> counted(std::span<const std::uint8_t> head, std::size_t count_at) {
  if (head.size() <= count_at) return std::nullopt;
  return count_at + 1 + head[count_at] + kCrcSize;
}

std::optional<std::size_t> reply_length(std::uint8_t function, std::span<const std::uint8_t> head) {
  if (function & kExceptionBit) return 5;  // address, function, code, CRC
  switch (function) {
    case 0x01: case 0x02: case 0x03: case 0x04:  // reads: a byte count, then the data
    case 0x11:                                   // report server id
    case 0x17:                                   // read/write multiple registers
      return counted(head, 2);
    case 0x05: case 0x06: case 0x0F: case 0x10:  // writes: address and value or count echoed
    case 0x08:                                   // diagnostics: sub-function and data echoed
      return 8;
    case 0x07:  // read exception status: one byte
      return 5;
    case 0x16:  // mask write register: the request echoed
      return 10;
    default:
      return kLengthByCrc;
  }
}

std::optional<std::size_t> request_length(std::uint8_t function,
                                          std::span<const std::uint8_t> head) {
  switch (function) {
    case 0x01: case 0x02: case 0x03: case 0x04: case 0x05: case 0x06:
    case 0x08:  // address (or sub-function) and a 16-bit value
      return 8;
    case 0x0F: case 0x10:  // address, count, byte count, data
      return counted(head, 6);
    case 0x07: case 0x0B: case 0x0C: case 0x11:  // no data
      return 4;
    case 0x16:
      return 10;
    case 0x17:
      return counted(head, 10);
    default:
      return kLengthByCrc;
  }
}

}  // namespace

std::optional<std::size_t> frame_length(FrameKind kind, std::span<const std::uint8_t> head) {
  if (head.size() < 2) return std::nullopt;
  return kind == FrameKind::reply ? reply_length(head[1], head) : request_length(head[1], head);
}

}  // namespace tiltgate::modbus_rtu
