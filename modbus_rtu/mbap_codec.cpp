#include "modbus_rtu/mbap_codec.h"

#include "modbus_rtu/big_endian.h"

namespace tiltgate::modbus_rtu {

std::vector<std::uint8_t> mbap_bytes(const MbapFrame& frame) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(kMbapHeaderSize + frame.pdu.size());
  put_u16(bytes, frame.transaction);
  put_u16(bytes, 0);  // protocol id: Modbus
  put_u16(bytes, static_cast<std::uint16_t>(1 + frame.pdu.size()));
  bytes.push_back(frame.unit);
  bytes.insert(bytes.end(), frame.pdu.begin(), frame.pdu.end());
  return bytes;
}

std::size_t MbapStream::feed(std::span<const std::uint8_t> bytes) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::size_t at = 0;
  while (buffer_.size() - at >= kMbapHeaderSize) {
    const std::span<const std::uint8_t> head(buffer_.data() + at, kMbapHeaderSize);
    const std::uint16_t protocol = get_u16(head, 2);
    const std::uint16_t length = get_u16(head, 4);
    if (protocol != 0 || length < kMbapMinLength || length > kMbapMaxLength) {
      ++at;  // not a frame start: look one byte further
      ++bytes_discarded_;
      continue;
    }
    const std::size_t size = 6u + length;
    if (buffer_.size() - at < size) break;  // the rest is still on its way
    MbapFrame frame;
    frame.transaction = get_u16(head, 0);
    frame.unit = head[6];
    frame.pdu.assign(buffer_.begin() + std::ptrdiff_t(at + kMbapHeaderSize),
                     buffer_.begin() + std::ptrdiff_t(at + size));
    ready_.push_back(std::move(frame));
    at += size;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + std::ptrdiff_t(at));
  return ready_.size();
}

std::optional<MbapFrame> MbapStream::next() {
  if (ready_.empty()) return std::nullopt;
  MbapFrame frame = std::move(ready_.front());
  ready_.pop_front();
  return frame;
}

void MbapStream::reset() {
  buffer_.clear();
  ready_.clear();
}

}  // namespace tiltgate::modbus_rtu
