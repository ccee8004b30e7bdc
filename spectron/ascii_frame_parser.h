// Finds Modbus-ASCII-style frames in a byte stream fed in arbitrary chunks. Pure: the
// transport feeds it; the driver, the simulator or a test takes the frames.
//
// Unlike the Rieker protocol a frame has a start marker, so resynchronising is simple: a ':'
// always starts a new frame (abandoning a partial one), bytes outside a frame are dropped, and
// a frame ends at CR LF. A partial frame is abandoned as soon as it cannot be valid: a
// character that is neither a hex digit nor its CR LF, a CR not followed by LF, or more than
// kMaxFrameLength characters. A complete frame is checked by decode() (digit count, LRC over
// the characters as received). The buffer never holds more than kMaxFrameLength characters.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>

#include "spectron/ascii_codec.h"
#include "spectron/assumptions.h"

namespace tiltgate::spectron {

struct AsciiParserCounters {
  std::uint64_t frames_ok = 0;
  std::uint64_t lrc_errors = 0;       // complete frames whose LRC did not match
  std::uint64_t malformed = 0;        // frames abandoned or rejected for anything else
  std::uint64_t bytes_discarded = 0;  // bytes outside frames, in dropped frames, or by reset()
};

class AsciiFrameParser {
 public:
  // Consumes all of `bytes`; returns how many good frames are waiting in next().
  std::size_t feed(std::span<const std::uint8_t> bytes);
  // The oldest good frame not yet taken.
  std::optional<AsciiFrame> next();
  // The characters of the frame next() returned last, as received (':' to CR LF): the LRC is
  // over them in their letter case, which a re-encoded frame would not keep.
  const std::string& last_text() const { return last_text_; }
  // Drops the partial frame and waiting frames: the start of a new exchange.
  void reset();

  std::size_t buffered() const { return size_; }
  const AsciiParserCounters& counters() const { return counters_; }

 private:
  void take(char c);
  void complete();
  void abandon();

  std::array<char, kMaxFrameLength> buffer_{};
  std::size_t size_ = 0;  // 0: outside a frame
  std::deque<AsciiFrame> ready_;
  std::deque<std::string> ready_text_;  // each ready frame's characters
  std::string last_text_;
  AsciiParserCounters counters_;
};

}  // namespace tiltgate::spectron
