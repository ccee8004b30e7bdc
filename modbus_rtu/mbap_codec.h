// Modbus TCP frames (Modbus Messaging on TCP/IP Implementation Guide V1.0b, 3.1.3): the MBAP
// header and a PDU, for devices that speak Modbus TCP themselves (protocol "modbus-tcp").
// Pure: bytes in, frames out, no I/O.
//
// An MBAP frame is: transaction id (2 bytes), protocol id (2, always 0 for Modbus), length (2,
// the bytes that follow: the unit id and the PDU), unit id (1), then the PDU. Big-endian.
//
// A TCP stream has no frame boundaries: a read may hold part of a frame or several. The header's
// length cuts the stream into frames; a header whose protocol id is not 0 or whose length no PDU
// can have is not a frame start, and its first byte is dropped to look again (a stream never
// needs that from a Modbus TCP device, but a reply broken off by a reconnect might).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

namespace tiltgate::modbus_rtu {

inline constexpr std::size_t kMbapHeaderSize = 7;  // up to and including the unit id
// The length field counts the unit id and the PDU: 1 + 1..253.
inline constexpr std::uint16_t kMbapMinLength = 2;
inline constexpr std::uint16_t kMbapMaxLength = 254;

struct MbapFrame {
  std::uint16_t transaction = 0;
  std::uint8_t unit = 0;
  std::vector<std::uint8_t> pdu;  // function code and data

  bool operator==(const MbapFrame&) const = default;
};

// The frame's bytes. The PDU must be 1..253 bytes (the caller's check: the RTU codec's).
std::vector<std::uint8_t> mbap_bytes(const MbapFrame& frame);

// Cuts a byte stream, fed in arbitrary chunks, into MBAP frames.
class MbapStream {
 public:
  // Consumes all of `bytes`; returns how many frames are waiting in next().
  std::size_t feed(std::span<const std::uint8_t> bytes);
  // The oldest frame not yet taken.
  std::optional<MbapFrame> next();
  // Drops buffered bytes and waiting frames: the start of a new exchange.
  void reset();

  std::size_t buffered() const { return buffer_.size(); }
  // Bytes dropped because they could not start a frame (not reset()'s).
  std::uint64_t bytes_discarded() const { return bytes_discarded_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::deque<MbapFrame> ready_;
  std::uint64_t bytes_discarded_ = 0;
};

}  // namespace tiltgate::modbus_rtu
