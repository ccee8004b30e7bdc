#include "modbus_rtu/frame_parser.h"

#include "modbus_rtu/crc.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::size_t kMinFrameSize = 4;  // address, function, CRC

}  // namespace

std::size_t RtuFrameParser::feed(std::span<const std::uint8_t> bytes) {
  for (std::uint8_t byte : bytes) push(byte);
  return ready_.size();
}

std::optional<Bytes> RtuFrameParser::next() {
  if (ready_.empty()) return std::nullopt;
  Bytes frame = std::move(ready_.front());
  ready_.pop_front();
  return frame;
}

void RtuFrameParser::reset() {
  counters_.bytes_discarded += buffer_.size();
  buffer_.clear();
  candidates_.clear();
  ready_.clear();
  at_frame_start_ = true;
}

void RtuFrameParser::push(std::uint8_t byte) {
  buffer_.push_back(byte);
  candidates_.push_back(Candidate{kCrcInitial, false, false});
  for (Candidate& c : candidates_) c.crc = crc16_update(c.crc, byte);
  for (std::size_t offset = 0; offset < buffer_.size(); ++offset) {
    if (completes_good(offset)) return take_frame(offset);
  }
  trim_front();
}

bool RtuFrameParser::plausible_start(std::size_t offset) const {
  const std::uint8_t address = buffer_[offset];
  const bool has_function = offset + 1 < buffer_.size();
  const std::uint8_t function = has_function ? buffer_[offset + 1] : 0;
  if (expect_) {
    return address == expect_->slave &&
           (!has_function || function == expect_->function ||
            function == (expect_->function | kExceptionBit));
  }
  if (kind_ == FrameKind::request)
    return address <= kMaxSlaveAddress && (!has_function || (function >= 1 && function < 0x80));
  return address <= kMaxSlaveAddress && (!has_function || function != 0);
}

bool RtuFrameParser::completes_good(std::size_t offset) {
  Candidate& candidate = candidates_[offset];
  if (candidate.dead || !plausible_start(offset)) return false;
  const auto head = std::span<const std::uint8_t>(buffer_).subspan(offset);
  const auto length = frame_length(kind_, head);
  if (!length) return false;
  if (*length > kMaxFrameSize) {  // a false start: a byte count no frame can hold
    candidate.dead = true;
    return false;
  }
  const bool by_crc = *length == kLengthByCrc;
  if (by_crc && head.size() > kMaxFrameSize) {  // no CRC matched within the largest frame
    candidate.dead = true;
    return false;
  }
  if (by_crc ? head.size() < kMinFrameSize : head.size() != *length) return false;
  if (candidate.crc == 0) return true;
  if (!by_crc) candidate.dead = candidate.crc_failed = true;  // a CRC-delimited one may end later
  return false;
}

void RtuFrameParser::take_frame(std::size_t offset) {
  drop_front(offset);
  ready_.emplace_back(buffer_.begin(), buffer_.end());
  buffer_.clear();
  candidates_.clear();
  ++counters_.frames_ok;
  at_frame_start_ = true;
}

void RtuFrameParser::trim_front() {
  while (!buffer_.empty()) {
    const Candidate& front = candidates_.front();
    if (!front.dead && plausible_start(0) && buffer_.size() <= kMaxFrameSize) return;
    if (front.crc_failed && at_frame_start_) {
      ++counters_.crc_errors;
      at_frame_start_ = false;
    }
    drop_front(1);
  }
}

void RtuFrameParser::drop_front(std::size_t count) {
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(count));
  candidates_.erase(candidates_.begin(), candidates_.begin() + static_cast<std::ptrdiff_t>(count));
  counters_.bytes_discarded += count;
}

}  // namespace tiltgate::modbus_rtu
