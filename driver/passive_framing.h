// How a listener that only hears a line cuts what it hears into frames: one function per
// protocol (ProtocolDescriptor::passive_framer), asked about the bytes from where a frame may
// start. The listener (capture/passive_decoder.h) owns the timing, the silences and the pairing
// of requests with replies; the protocol only says what the bytes in front of it are. Pure:
// no I/O, no state, so a family's framer is tested on byte vectors like its codec.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace tiltgate {

// The frame a listener asks about: one the master sends, or one a device sends back.
enum class PassiveRole : std::uint8_t { request, reply };

// What the bytes heard start with, read as one role.
struct PassiveCut {
  enum class Kind : std::uint8_t {
    need_more,    // could still be such a frame: its end has not arrived
    frame,        // a whole frame of `length` bytes, its check good or bad
    not_a_start,  // no such frame starts at the first byte
  };
  Kind kind = Kind::need_more;
  std::size_t length = 0;  // frame: how many of the bytes it takes
  // frame: its checksum matched (for a protocol without one: its form is whole).
  bool intact = false;
  // frame: the check in a few words, a literal: "CRC ok", "bad CRC", "LRC ok", "bad LRC".
  std::string_view verdict;
  // frame: leading bytes the master sent with the ninth bit set (a 9-bit bus's address byte).
  std::uint8_t address_bytes = 0;

  static constexpr PassiveCut need_more() { return of(Kind::need_more); }
  static constexpr PassiveCut not_a_start() { return of(Kind::not_a_start); }
  static constexpr PassiveCut of(Kind kind) {
    PassiveCut cut;
    cut.kind = kind;
    return cut;
  }
  static constexpr PassiveCut whole(std::size_t length, bool intact, std::string_view verdict,
                                    std::uint8_t address_bytes = 0) {
    return {Kind::frame, length, intact, verdict, address_bytes};
  }
};

// `heard`: the bytes from a possible frame start on (any number, a whole frame or part of one,
// or several frames). `role`: the frame wanted. `request`: for a reply, the request it would
// answer, as heard, so a protocol whose replies name their request's device or function takes
// only those; empty: any reply (no request was heard before it). A protocol answers not_a_start
// for a frame that is whole and good but is not the reply to `request`: the listener then
// reads the same bytes as the next request.
using PassiveFramer = PassiveCut (*)(std::span<const std::uint8_t> heard, PassiveRole role,
                                     std::span<const std::uint8_t> request);

}  // namespace tiltgate
