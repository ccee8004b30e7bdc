// Finds Rieker frames in a byte stream fed in arbitrary chunks (a serial read returns whatever
// has arrived). Pure: the transport feeds it, the driver or the simulator takes the frames.
//
// Resynchronisation strategy. A frame carries no start marker, so any byte may be a frame's
// first, and a false start can claim DL up to 255 and so "need" 264 bytes. Rather than commit
// to the first header and wait for its bytes, the parser looks at every buffered offset and
// takes the earliest one whose frame is complete and passes its CRC. So a short valid reply
// that arrives right after a garbage byte is found as soon as its own bytes are in, whatever
// length the garbage claimed. Leading bytes are dropped one at a time once the frame they
// would start is complete and fails its CRC: they can never start a valid frame. A leading
// false start still waiting for bytes is kept (it might yet be a real frame) until a valid
// frame after it is found, or until the owner calls reset() (the driver does before every
// attempt, so its reply timeout bounds the wait).
//
// Every candidate frame's CRC is computed once, when its last byte arrives. The buffer never
// holds more than kMaxFrameSize bytes: a leading candidate that long is always complete.
// The one risk of scanning every offset: a frame still arriving may contain, among the bytes
// received so far, 9+ bytes that happen to form a frame with a valid CRC (about 1 in 65536 per
// offset for random bytes); checking is_reply_to() on what is found catches most of those.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>

#include "rieker/codec.h"

namespace tiltgate::rieker {

struct ParserCounters {
  std::uint64_t frames_ok = 0;
  // Stretches of bytes that started where a frame was due (after reset() or a good frame) and
  // did not form a frame with a good CRC: a corrupted frame counts once, not once per byte.
  std::uint64_t crc_errors = 0;
  std::uint64_t bytes_discarded = 0;  // bytes dropped while resynchronising, or by reset()
};

class RiekerFrameParser {
 public:
  // Consumes all of `bytes`; returns how many good frames are waiting in next().
  std::size_t feed(std::span<const std::uint8_t> bytes);
  // The oldest good frame not yet taken.
  std::optional<Frame> next();
  // The last frame that was complete where a frame was due but failed its CRC (its header and
  // data as received), taken once: a sensor answers it with NAK 0 when it is addressed to it.
  std::optional<Frame> take_crc_failure();
  // Drops buffered bytes and waiting frames: the start of a new exchange.
  void reset();

  std::size_t buffered() const { return size_; }
  const ParserCounters& counters() const { return counters_; }

 private:
  // Where the candidate starting at `offset` ends, or nullopt before its DL byte arrived.
  std::optional<std::size_t> candidate_end(std::size_t offset) const;
  bool crc_ok(std::size_t offset, std::size_t end) const;
  // The earliest offset holding a complete frame with a good CRC among the candidates that
  // ended after `checked` (those ending at or before it were looked at by an earlier pass).
  std::optional<std::size_t> find_good_frame(std::size_t checked) const;
  void scan(std::size_t checked);
  void take_frame(std::size_t end);
  void discard_front(std::size_t count);

  std::array<std::uint8_t, kMaxFrameSize> buffer_{};
  std::size_t size_ = 0;
  bool at_frame_start_ = true;  // buffer_[0] is where a frame was due
  std::deque<Frame> ready_;
  std::optional<Frame> crc_failure_;
  ParserCounters counters_;
};

}  // namespace tiltgate::rieker
