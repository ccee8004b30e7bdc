// The Rieker Flex protocol (rieker/): the frame parser fed a byte stream in random-sized reads,
// every frame it finds re-encoded and decoded back unchanged and given to every reply decoder;
// and the whole input decoded as one frame, which must re-encode to the same bytes.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz/chunks.h"
#include "rieker/codec.h"
#include "rieker/frame_parser.h"

using namespace tiltgate::rieker;
using tiltgate::fuzz::check;

namespace {

void decode_replies(const Frame& frame) {
  (void)parse_ack(frame);
  (void)parse_address_reply(frame);
  for (auto type : {AngleType::single_axis, AngleType::x, AngleType::y, AngleType::x_and_y}) {
    auto angles = parse_angle_reply(frame, type);
    if (angles) check(angles->x.has_value() || angles->y.has_value());
  }
  (void)parse_firmware_reply(frame);
  (void)parse_lock_level_reply(frame);
  (void)parse_serial_reply(frame);
  (void)function_name(frame.function);
  if (!frame.data.empty()) (void)nak_name(frame.data[0]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::uint8_t> input(data, size);
  if (auto whole = decode(input)) {
    std::vector<std::uint8_t> again = encode(*whole);
    check(std::vector<std::uint8_t>(input.begin(), input.end()) == again);
    decode_replies(*whole);
  }

  tiltgate::fuzz::Chunks reads(input);
  RiekerFrameParser parser;
  std::size_t fed = 0;
  while (!reads.done()) {
    auto piece = reads.next();
    fed += piece.size();
    parser.feed(piece);
    check(parser.buffered() <= kMaxFrameSize);
    while (auto frame = parser.next()) {
      check(frame->data.size() <= kMaxDataSize);
      auto bytes = encode(*frame);
      auto back = decode(bytes);
      check(back.has_value() && *back == *frame);
      decode_replies(*frame);
    }
    if (auto failed = parser.take_crc_failure()) check(failed->data.size() <= kMaxDataSize);
  }
  // Every byte fed is in a frame, still buffered, or counted as discarded.
  const auto& counters = parser.counters();
  check(counters.bytes_discarded + parser.buffered() <= fed);
  return 0;
}
