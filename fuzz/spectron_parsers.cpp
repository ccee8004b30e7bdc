// Both Spectron SPECTROTILT Dyna protocols (spectron/): the 9-bit ASCII line parser and the
// Modbus-ASCII (LRC) frame parser, each fed the input in random-sized reads. Every 9-bit line
// goes to the number, firmware and command decoders; every ASCII frame must decode again from
// the characters it arrived as, re-encode to a frame that decodes to itself, and go through
// the reply decoders.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "fuzz/chunks.h"
#include "spectron/ascii_codec.h"
#include "spectron/ascii_frame_parser.h"
#include "spectron/nine_bit_codec.h"

using namespace tiltgate::spectron;
using tiltgate::fuzz::check;

namespace {

void nine_bit(std::span<const std::uint8_t> input) {
  tiltgate::fuzz::Chunks reads(input);
  NineBitLineParser parser;
  while (!reads.done()) {
    parser.feed(reads.next());
    while (auto line = parser.next()) {
      (void)parse_nine_bit_number(*line);
      (void)parse_nine_bit_firmware(*line);
      (void)parse_nine_bit_body(*line);
    }
  }
}

void decode_replies(const AsciiFrame& frame) {
  auto request = ascii_read_sensor_request(frame.address);
  if (!request) return;
  AsciiFrame asked = *request;
  (void)parse_ascii_sensor_reply(frame, asked);
  (void)parse_ascii_temperature_reply(frame, asked);
  (void)parse_ascii_eeprom_reply(frame, asked);
  (void)parse_ascii_revision_reply(frame, asked);
  (void)parse_ascii_ack(frame, asked);
  (void)is_reply_to(frame, asked);
  for (std::size_t i = 0; i <= frame.data.size() / 2; ++i) (void)word_at(frame, i);
}

void modbus_ascii(std::span<const std::uint8_t> input) {
  std::string_view text(reinterpret_cast<const char*>(input.data()), input.size());
  if (auto whole = decode(text)) {
    auto again = decode(encode_text(*whole));
    check(again.has_value() && *again == *whole);
  }

  tiltgate::fuzz::Chunks reads(input);
  AsciiFrameParser parser;
  while (!reads.done()) {
    parser.feed(reads.next());
    while (auto frame = parser.next()) {
      auto again = decode(parser.last_text());
      check(again.has_value() && *again == *frame);
      auto encoded = decode(encode_text(*frame));
      check(encoded.has_value() && *encoded == *frame);
      decode_replies(*frame);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::uint8_t> input(data, size);
  nine_bit(input);
  modbus_ascii(input);
  return 0;
}
