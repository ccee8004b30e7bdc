#include "rieker/frame_parser.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "rieker/bytes.h"
#include "rieker/crc16.h"

namespace tiltgate::rieker {

std::size_t RiekerFrameParser::feed(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const std::size_t count = std::min(bytes.size(), buffer_.size() - size_);
    std::memcpy(buffer_.data() + size_, bytes.data(), count);
    const std::size_t checked = size_;
    size_ += count;
    bytes = bytes.subspan(count);
    scan(checked);
  }
  return ready_.size();
}

std::optional<Frame> RiekerFrameParser::next() {
  if (ready_.empty()) return std::nullopt;
  Frame frame = std::move(ready_.front());
  ready_.pop_front();
  return frame;
}

std::optional<Frame> RiekerFrameParser::take_crc_failure() {
  return std::exchange(crc_failure_, std::nullopt);
}

void RiekerFrameParser::reset() {
  counters_.bytes_discarded += size_;
  size_ = 0;
  at_frame_start_ = true;
  ready_.clear();
  crc_failure_.reset();
}

std::optional<std::size_t> RiekerFrameParser::candidate_end(std::size_t offset) const {
  if (offset + kHeaderSize > size_) return std::nullopt;
  return offset + kMinFrameSize + buffer_[offset + kHeaderSize - 1];
}

bool RiekerFrameParser::crc_ok(std::size_t offset, std::size_t end) const {
  const std::size_t crc_at = end - kCrcSize;
  return crc16(std::span(buffer_.data() + offset, crc_at - offset)) == get_u16(&buffer_[crc_at]);
}

std::optional<std::size_t> RiekerFrameParser::find_good_frame(std::size_t checked) const {
  for (std::size_t offset = 0; offset + kMinFrameSize <= size_; ++offset) {
    const auto end = candidate_end(offset);
    if (!end) break;  // later offsets have no DL byte either
    if (*end > size_ || *end <= checked) continue;
    if (crc_ok(offset, *end)) return offset;
  }
  return std::nullopt;
}

void RiekerFrameParser::scan(std::size_t checked) {
  while (const auto offset = find_good_frame(checked)) {
    discard_front(*offset);
    const std::size_t end = *candidate_end(0);
    take_frame(end);
    checked = checked > *offset + end ? checked - (*offset + end) : 0;
  }
  // A leading candidate that is complete has failed its CRC (or it would have been taken), and
  // no later byte can change that: drop its first byte and look at the next one.
  for (auto end = candidate_end(0); end && *end <= size_; end = candidate_end(0)) {
    discard_front(1);
  }
}

void RiekerFrameParser::take_frame(std::size_t end) {
  Frame frame;
  frame.dest = get_u16(&buffer_[0]);
  frame.src = get_u16(&buffer_[2]);
  frame.function = get_u16(&buffer_[4]);
  frame.data.assign(buffer_.begin() + kHeaderSize,
                    buffer_.begin() + static_cast<std::ptrdiff_t>(end - kCrcSize));
  ready_.push_back(std::move(frame));
  ++counters_.frames_ok;
  std::memmove(buffer_.data(), buffer_.data() + end, size_ - end);
  size_ -= end;
  at_frame_start_ = true;
}

void RiekerFrameParser::discard_front(std::size_t count) {
  if (count == 0) return;
  if (at_frame_start_) {
    ++counters_.crc_errors;
    const auto end = candidate_end(0);
    if (end && *end <= size_) {
      // Keep what arrived (minus the CRC) so a sensor can NAK 0 the sender.
      crc_failure_ = Frame{get_u16(&buffer_[0]), get_u16(&buffer_[2]), get_u16(&buffer_[4]),
                           {buffer_.begin() + kHeaderSize,
                            buffer_.begin() + static_cast<std::ptrdiff_t>(*end - kCrcSize)}};
    }
    at_frame_start_ = false;
  }
  counters_.bytes_discarded += count;
  std::memmove(buffer_.data(), buffer_.data() + count, size_ - count);
  size_ -= count;
}

}  // namespace tiltgate::rieker
