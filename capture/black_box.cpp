#include "capture/black_box.h"

#include <algorithm>
#include <cstring>

namespace tiltgate {

namespace {

// The most verdicts kept apart; any further one is kept as this (a framer that words each
// rejection differently must not grow the table without end).
constexpr std::size_t kMaxVerdicts = 255;
const std::string kOtherVerdict = "other";

template <typename T>
void put_packed(std::vector<std::uint8_t>& out, T value) {
  const auto at = out.size();
  out.resize(at + sizeof value);
  std::memcpy(out.data() + at, &value, sizeof value);
}

template <typename T>
T get_packed(const std::vector<std::uint8_t>& in, std::size_t& offset) {
  T value{};
  std::memcpy(&value, in.data() + offset, sizeof value);
  offset += sizeof value;
  return value;
}

}  // namespace

// A packed frame: steady time (8), wall time in microseconds (8), direction and address
// bytes (1: the direction in the top bit), verdict index (1), length (2), then its bytes.
static_assert(BlackBox::kFrameOverhead == 8 + 8 + 1 + 1 + 2 + 1,
              "the header, and one byte of the block's slack a frame leaves on average");

BlackBox::BlackBox(std::chrono::seconds keep)
    : keep_(keep),
      limit_(std::max<std::size_t>(std::size_t(std::max<std::int64_t>(keep.count(), 1)) *
                                       kBytesPerSecond,
                                   2 * kBlockBytes)) {}

void BlackBox::record(const FrameView& frame) { record(frame, Clock::now()); }

void BlackBox::record(const CapturedFrame& frame, Clock::time_point now) {
  record(FrameView{frame.time, frame.direction, frame.bytes, frame.address_bytes, frame.verdict},
         now);
}

std::uint8_t BlackBox::verdict_index(std::string_view verdict) {
  for (std::size_t i = 0; i < verdicts_.size(); ++i)
    if (verdicts_[i] == verdict) return std::uint8_t(i);
  if (verdicts_.size() < kMaxVerdicts) {
    verdicts_.emplace_back(verdict);
    return std::uint8_t(verdicts_.size() - 1);
  }
  return std::uint8_t(kMaxVerdicts);  // kOtherVerdict
}

void BlackBox::pack(const FrameView& frame, Clock::time_point at) {
  // A frame longer than the length field holds is cut (none is: a line's frames are short).
  const std::size_t length = std::min<std::size_t>(frame.bytes.size(), 0xFFFF);
  const std::size_t size = kFrameOverhead - 1 + length;
  if (blocks_.empty() || blocks_.back().bytes.size() + size > blocks_.back().bytes.capacity()) {
    Block block;
    block.bytes.reserve(std::max(kBlockBytes, size));
    block.first = next_number_;
    blocks_.push_back(std::move(block));
  }
  Block& block = blocks_.back();
  const auto micros =
      std::chrono::duration_cast<std::chrono::microseconds>(frame.time.time_since_epoch());
  put_packed<std::int64_t>(block.bytes, at.time_since_epoch().count());
  put_packed<std::int64_t>(block.bytes, micros.count());
  const auto direction = std::uint8_t(frame.direction == FrameDirection::from_devices ? 0x80 : 0);
  put_packed<std::uint8_t>(block.bytes, std::uint8_t(direction | (frame.address_bytes & 0x7F)));
  put_packed<std::uint8_t>(block.bytes, verdict_index(frame.verdict));
  put_packed<std::uint16_t>(block.bytes, std::uint16_t(length));
  block.bytes.insert(block.bytes.end(), frame.bytes.begin(), frame.bytes.begin() + long(length));
  ++block.count;
  block.newest = at;
}

void BlackBox::record(const FrameView& frame, Clock::time_point now) {
  pack(frame, now);
  ++next_number_;
  const Clock::time_point oldest = now - keep_;
  while (blocks_.size() > 1 && blocks_.front().newest < oldest) blocks_.pop_front();
  while (blocks_.size() > 1 && bytes_held() > limit_) {
    dropped_ += blocks_.front().count;
    blocks_.pop_front();
  }
}

CapturedFrame BlackBox::unpack(const Block& block, std::size_t& offset, Clock::time_point oldest,
                               bool& old_enough) const {
  CapturedFrame frame;
  const Clock::time_point at{Clock::duration(get_packed<std::int64_t>(block.bytes, offset))};
  frame.time = std::chrono::system_clock::time_point(
      std::chrono::microseconds(get_packed<std::int64_t>(block.bytes, offset)));
  const auto direction = get_packed<std::uint8_t>(block.bytes, offset);
  frame.direction = (direction & 0x80) != 0 ? FrameDirection::from_devices
                                            : FrameDirection::to_devices;
  frame.address_bytes = std::uint8_t(direction & 0x7F);
  const auto verdict = get_packed<std::uint8_t>(block.bytes, offset);
  const auto length = get_packed<std::uint16_t>(block.bytes, offset);
  old_enough = at >= oldest;
  if (old_enough) {
    frame.verdict = verdict < verdicts_.size() ? verdicts_[verdict] : kOtherVerdict;
    frame.bytes.assign(block.bytes.begin() + long(offset),
                       block.bytes.begin() + long(offset + length));
  }
  offset += length;
  return frame;
}

BlackBox::Slice BlackBox::since(std::uint64_t after, std::size_t limit) const {
  Slice slice;
  slice.next = std::max(after, newest());
  if (after >= newest() || blocks_.empty()) return slice;
  const Clock::time_point oldest = blocks_.back().newest - keep_;
  std::uint64_t expected = after + 1;  // the next number the reader has not had
  for (const Block& block : blocks_) {
    if (block.first + block.count <= expected) continue;  // all had
    std::size_t offset = 0;
    for (std::uint32_t i = 0; i < block.count; ++i) {
      const std::uint64_t number = block.first + i;
      if (number < expected) {  // had: step over it
        bool unused = false;
        (void)unpack(block, offset, Clock::time_point::max(), unused);
        continue;
      }
      if (slice.frames.size() >= limit) {
        slice.next = number - 1;
        return slice;
      }
      bool kept = false;
      CapturedFrame frame = unpack(block, offset, oldest, kept);
      if (!kept) continue;  // too old: counted as missed below
      slice.missed += number - expected;
      slice.frames.push_back(std::move(frame));
      expected = number + 1;
    }
  }
  slice.missed += newest() + 1 - expected;
  return slice;
}

std::vector<CapturedFrame> BlackBox::held() const { return since(0).frames; }

std::size_t BlackBox::frames_held() const {
  std::size_t frames = 0;
  for (const Block& block : blocks_) frames += block.count;
  return frames;
}

}  // namespace tiltgate
