// A bus's black box: every frame its line carried in the last `keep` seconds ([[bus]]
// black_box_s, 60 by default), in memory, so that when a sensor stops answering the minute
// before is still there to be written as a pcapng file (capture/pcapng.h) by
// `tiltgate capture --last` or the console's download; and the frames a live capture or the
// console's traffic view reads as they come (since()).
//
// Frames are kept packed, one after another in blocks of kBlockBytes: each its times, its
// direction and address bytes, its verdict as an index into the few verdicts a line says, and
// its bytes; 21 bytes besides its own. So a saturated 125000-baud line (about 600 frames a
// second of 10 and 17 bytes) keeps a minute in about 1.6 MB. Memory is bounded twice: by age
// (a block goes once its newest frame is older than `keep`; older frames in a kept block are
// not given out), and by kBytesPerSecond x keep bytes of blocks, past which the oldest block
// goes before its time (its frames counted in dropped()). docs/diagnostics.md, "The black box".
//
// Age counts back from the newest frame, not from now: a line that fell silent (its adapter
// unplugged, every device gone) keeps the minute before, which is what is looked for then.
//
// On the buses' executor, like the line that records into it; nothing here locks.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "driver/captured_frame.h"

namespace tiltgate {

class BlackBox final : public FrameRecorder {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kBytesPerSecond = 48 * 1024;
  static constexpr std::size_t kBlockBytes = 16 * 1024;
  // What a frame costs besides its bytes (packed_frame's header).
  static constexpr std::size_t kFrameOverhead = 21;

  explicit BlackBox(std::chrono::seconds keep);

  void record(const FrameView& frame) override;
  // As record(), at `now` (tests).
  void record(const FrameView& frame, Clock::time_point now);
  void record(const CapturedFrame& frame, Clock::time_point now);

  // Frames numbered after `after`, oldest first, at most `limit`; `next` is the number to ask
  // after next time, `missed` how many frames after `after` were gone before this call (too old,
  // or pushed out by the memory bound).
  struct Slice {
    std::vector<CapturedFrame> frames;
    std::uint64_t next = 0;
    std::uint64_t missed = 0;
  };
  Slice since(std::uint64_t after, std::size_t limit = SIZE_MAX) const;
  // Every frame of the `keep` seconds up to the newest.
  std::vector<CapturedFrame> held() const;
  // The number of the newest frame (0: none yet): a live capture starts after it.
  std::uint64_t newest() const { return next_number_ - 1; }

  std::chrono::seconds keep() const override { return keep_; }
  std::size_t frames_held() const;
  // The memory its blocks take.
  std::size_t bytes_held() const { return blocks_.size() * kBlockBytes; }
  std::size_t byte_limit() const { return limit_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  struct Block {
    std::vector<std::uint8_t> bytes;  // reserved kBlockBytes, frames packed end to end
    std::uint64_t first = 0;          // the number of its first frame
    std::uint32_t count = 0;
    Clock::time_point newest{};       // when its last frame was recorded
  };
  // Appends `frame` recorded at `at` to the last block.
  void pack(const FrameView& frame, Clock::time_point at);
  // The frame at `offset` of `block`, and where the next one starts; none when it is older
  // than `oldest`.
  CapturedFrame unpack(const Block& block, std::size_t& offset, Clock::time_point oldest,
                       bool& old_enough) const;
  std::uint8_t verdict_index(std::string_view verdict);

  std::chrono::seconds keep_;
  std::size_t limit_;
  std::deque<Block> blocks_;
  // The verdicts a line says: "request", "CRC ok", "no reply: bad CRC"... each kept once.
  std::vector<std::string> verdicts_;
  std::uint64_t next_number_ = 1;
  std::uint64_t dropped_ = 0;  // pushed out by the memory bound before their time
};

}  // namespace tiltgate
