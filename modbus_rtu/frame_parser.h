// Finds Modbus RTU frames in a byte stream fed in arbitrary chunks (a serial read returns
// whatever has arrived). Pure: the Line or the simulator feeds it and takes the frames.
//
// A frame has no start marker; on a real line the 3.5-character silence delimits it, but a
// USB adapter's reads lose that timing, so the parser frames by content: a frame's length
// follows from its function code (modbus_rtu/frame_length.h) and its CRC confirms it. Like
// the Rieker parser it considers every buffered offset as a frame start and takes the first
// frame to complete with a good CRC, so garbage before a frame (line noise, a late reply's
// tail) costs nothing but its bytes, even when it looks like the start of a long frame.
// Leading bytes are dropped once they cannot start a valid frame: not a plausible start (see
// Expectation), a complete frame with a bad CRC, or more than a frame's 256 bytes ago.
//
// Cost: one running CRC per buffered offset, updated with each byte (the CRC of a frame with
// its CRC appended is 0), so every byte costs O(buffered bytes), at most 256.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "modbus_rtu/codec.h"
#include "modbus_rtu/frame_length.h"

namespace tiltgate::modbus_rtu {

// What a frame must start with to be taken: a reply from this slave to this function (or its
// exception). Without one, any address 0..247 and function code 1..127 (requests), or any
// function code but 0 (replies), qualify.
struct Expectation {
  std::uint8_t slave = 0;
  std::uint8_t function = 0;
};

struct ParserCounters {
  std::uint64_t frames_ok = 0;
  // Complete frames that failed their CRC where a frame was due (after reset() or a good
  // frame): a corrupted frame counts once, not again for each false start inside it. Noise
  // that looks like a frame's start (an address and a function code) counts too.
  std::uint64_t crc_errors = 0;
  std::uint64_t bytes_discarded = 0;  // dropped while resynchronising, or by reset()
};

class RtuFrameParser {
 public:
  explicit RtuFrameParser(FrameKind kind, std::optional<Expectation> expect = std::nullopt)
      : kind_(kind), expect_(expect) {}

  // Consumes all of `bytes`; returns how many good frames are waiting in next().
  std::size_t feed(std::span<const std::uint8_t> bytes);
  // The oldest good frame not yet taken, CRC included.
  std::optional<Bytes> next();
  // Drops buffered bytes and waiting frames: the start of a new exchange.
  void reset();

  std::size_t buffered() const { return buffer_.size(); }
  const ParserCounters& counters() const { return counters_; }

 private:
  struct Candidate {
    std::uint16_t crc = 0;     // running CRC from this offset to the end of the buffer
    bool dead = false;         // cannot start a good frame any more
    bool crc_failed = false;   // dead because it was complete with a bad CRC
  };

  void push(std::uint8_t byte);
  bool plausible_start(std::size_t offset) const;
  // Checks the frame starting at `offset` if it ends with the last byte pushed: true when it
  // is good; marks it bad when it is complete and is not.
  bool completes_good(std::size_t offset);
  void take_frame(std::size_t offset);
  void trim_front();
  void drop_front(std::size_t count);

  FrameKind kind_;
  std::optional<Expectation> expect_;
  std::vector<std::uint8_t> buffer_;
  std::vector<Candidate> candidates_;  // one per buffered byte
  bool at_frame_start_ = true;
  std::deque<Bytes> ready_;
  ParserCounters counters_;
};

}  // namespace tiltgate::modbus_rtu
