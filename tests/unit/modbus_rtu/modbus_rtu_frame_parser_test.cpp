// The RTU frame parser and reply framer: whole frames vs byte at a time, random chunks,
// garbage and false starts before a frame, corrupted frames, frames framed only by their CRC.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "modbus_rtu/frame_parser.h"
#include "modbus_rtu/reply_framer.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using test::framed;
using test::hex;

namespace {

std::vector<Bytes> drain(RtuFrameParser& parser) {
  std::vector<Bytes> frames;
  while (auto frame = parser.next()) frames.push_back(std::move(*frame));
  return frames;
}

// Feeds `stream` in chunks of 1..max_chunk bytes (max_chunk 0: all at once).
std::vector<Bytes> parse(RtuFrameParser& parser, const Bytes& stream, std::mt19937& rng,
                         std::size_t max_chunk) {
  std::vector<Bytes> frames;
  std::size_t at = 0;
  while (at < stream.size()) {
    std::size_t n = stream.size() - at;
    if (max_chunk > 0)
      n = std::min(n, std::uniform_int_distribution<std::size_t>(1, max_chunk)(rng));
    parser.feed(std::span(stream).subspan(at, n));
    at += n;
    for (auto& frame : drain(parser)) frames.push_back(std::move(frame));
    REQUIRE(parser.buffered() <= kMaxFrameSize);
  }
  return frames;
}

Bytes random_request(std::mt19937& rng) {
  std::uniform_int_distribution<int> slave(1, 247), word(0, 0xFFFF), count(1, 10), kind(0, 2);
  const auto s = static_cast<std::uint8_t>(slave(rng));
  const auto address = static_cast<std::uint16_t>(word(rng) % 1000);
  switch (kind(rng)) {
    case 0: return read_request(s, RegisterBank::input, address, std::uint16_t(count(rng)))->frame;
    case 1: return write_single_request(s, address, std::uint16_t(word(rng)))->frame;
    default: {
      std::vector<std::uint16_t> values(static_cast<std::size_t>(count(rng)));
      for (auto& v : values) v = static_cast<std::uint16_t>(word(rng));
      return write_multiple_request(s, address, values)->frame;
    }
  }
}

const Request kRead17 = *read_request(17, RegisterBank::holding, 107, 3);
const Bytes kReply17 = hex("11 03 06 AE 41 56 52 43 40 49 AD");

}  // namespace

TEST_CASE("RTU parser: a whole frame and the same frame byte at a time give the same frame") {
  RtuFrameParser whole(FrameKind::reply);
  CHECK(whole.feed(kReply17) == 1);
  RtuFrameParser bytewise(FrameKind::reply);
  for (std::size_t i = 0; i < kReply17.size(); ++i) {
    CHECK(bytewise.feed(std::span(kReply17).subspan(i, 1)) == (i + 1 == kReply17.size() ? 1u : 0u));
  }
  CHECK(drain(whole) == std::vector<Bytes>{kReply17});
  CHECK(drain(bytewise) == std::vector<Bytes>{kReply17});
}

TEST_CASE("RTU parser: requests in random chunks with garbage between come out in order") {
  std::mt19937 rng(42);
  std::vector<Bytes> sent;
  Bytes stream;
  for (int i = 0; i < 200; ++i) {
    sent.push_back(random_request(rng));
    stream.insert(stream.end(), sent.back().begin(), sent.back().end());
    if (i % 7 == 3) stream.push_back(0xFF);  // line noise: 255 is no slave address
  }
  for (std::size_t max_chunk : {0u, 1u, 3u, 17u, 64u}) {
    CAPTURE(max_chunk);
    RtuFrameParser parser(FrameKind::request);
    CHECK(parse(parser, stream, rng, max_chunk) == sent);
    CHECK(parser.counters().frames_ok == sent.size());
    CHECK(parser.counters().crc_errors == 0);
  }
}

TEST_CASE("RTU parser: a false start claiming a long frame does not hide the reply after it") {
  // 11 03 FA claims 250 data bytes; the real reply follows at once.
  Bytes stream = hex("11 03 FA 00");
  stream.insert(stream.end(), kReply17.begin(), kReply17.end());
  std::mt19937 rng(1);
  for (std::size_t max_chunk : {0u, 1u, 5u}) {
    RtuFrameParser parser(FrameKind::reply, Expectation{17, kReadHoldingRegisters});
    CHECK(parse(parser, stream, rng, max_chunk) == std::vector<Bytes>{kReply17});
  }
}

TEST_CASE("RTU parser: a corrupted frame counts one CRC error and the next frame is found") {
  Bytes corrupted = kReply17;
  corrupted[5] ^= 0x10;
  Bytes stream = corrupted;
  stream.insert(stream.end(), kReply17.begin(), kReply17.end());
  RtuFrameParser parser(FrameKind::reply);
  parser.feed(stream);
  CHECK(drain(parser) == std::vector<Bytes>{kReply17});
  CHECK(parser.counters().crc_errors == 1);
  CHECK(parser.counters().bytes_discarded == corrupted.size());
}

TEST_CASE("RTU parser: a frame of a function it does not know ends where its CRC matches") {
  const Bytes unusual = framed("1E 2B 0E 01 01 00 00 01 00 03 41 42 43");
  RtuFrameParser parser(FrameKind::reply, Expectation{30, 0x2B});
  Bytes stream = hex("00 1E");  // noise, and a false start
  stream.insert(stream.end(), unusual.begin(), unusual.end());
  std::mt19937 rng(3);
  CHECK(parse(parser, stream, rng, 1) == std::vector<Bytes>{unusual});
}

// Found by the modbus_rtu_codec fuzzer: a CRC-delimited frame was taken when its CRC matched
// at byte 257, one past the largest RTU frame (Serial Line 2.5.1.1), so a pass-through could
// relay a PDU too long for a Modbus TCP reply.
TEST_CASE("RTU parser: a frame of a function it does not know is at most 256 bytes") {
  auto unknown_function_frame = [](std::size_t size) {
    Bytes frame{0x01, 0x31};  // function 0x31: no length rule, so the CRC ends it
    frame.resize(size - 2, 0x00);
    const std::uint16_t crc = test::reference_crc(frame);
    frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
    frame.push_back(static_cast<std::uint8_t>(crc >> 8));
    return frame;
  };
  std::mt19937 rng(5);
  const Bytes largest = unknown_function_frame(kMaxFrameSize);
  RtuFrameParser parser(FrameKind::request);
  CHECK(parse(parser, largest, rng, 7) == std::vector<Bytes>{largest});

  const Bytes too_long = unknown_function_frame(kMaxFrameSize + 1);
  RtuFrameParser long_parser(FrameKind::request);
  CHECK(parse(long_parser, too_long, rng, 7).empty());
}

TEST_CASE("RTU parser: reset forgets a partial frame") {
  RtuFrameParser parser(FrameKind::reply);
  parser.feed(std::span(kReply17).first(6));
  parser.reset();
  CHECK(parser.buffered() == 0);
  parser.feed(kReply17);
  CHECK(drain(parser) == std::vector<Bytes>{kReply17});
}

TEST_CASE("RTU reply framer: done only once the whole reply is in") {
  RtuReplyFramer framer(kRead17);
  framer.reset();
  for (std::size_t i = 0; i + 1 < kReply17.size(); ++i)
    REQUIRE_FALSE(framer.feed(std::span(kReply17).subspan(i, 1)));
  CHECK(framer.feed(std::span(kReply17).last(1)));
  REQUIRE(framer.reply().has_value());
  REQUIRE(framer.reply()->has_value());
  CHECK((*framer.reply())->registers == std::vector<std::uint16_t>{0xAE41, 0x5652, 0x4340});
}

TEST_CASE("RTU reply framer: skips garbage, other slaves and bad CRCs before the reply") {
  RtuReplyFramer framer(kRead17);
  Bytes stream = hex("00 FF 11");
  const Bytes other_slave = framed("12 03 06 00 01 00 02 00 03");
  stream.insert(stream.end(), other_slave.begin(), other_slave.end());
  Bytes corrupted = kReply17;
  corrupted.back() ^= 0x01;
  stream.insert(stream.end(), corrupted.begin(), corrupted.end());
  stream.insert(stream.end(), kReply17.begin(), kReply17.end());
  CHECK(framer.feed(stream));
  REQUIRE(framer.reply()->has_value());
  CHECK((*framer.reply())->registers.size() == 3);
  CHECK(framer.crc_errors() == 1);
}

TEST_CASE("RTU reply framer: an exception ends the wait, and so does a reply that fails its checks") {
  RtuReplyFramer refused(kRead17);
  CHECK(refused.feed(hex("11 83 02 C1 34")));
  CHECK((*refused.reply())->exception == std::optional<std::uint8_t>(2));

  RtuReplyFramer short_reply(kRead17);
  CHECK(short_reply.feed(framed("11 03 02 00 01")));
  REQUIRE_FALSE(short_reply.reply()->has_value());
  CHECK(short_reply.reply()->error() == CodecError::bad_byte_count);

  short_reply.reset();
  CHECK_FALSE(short_reply.reply().has_value());
}

TEST_CASE("RTU parser and reply checks survive random bytes") {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  for (FrameKind kind : {FrameKind::request, FrameKind::reply}) {
    RtuFrameParser parser(kind);
    Bytes noise(20000);
    for (auto& b : noise) b = static_cast<std::uint8_t>(byte(rng));
    for (const Bytes& frame : parse(parser, noise, rng, 40)) {
      CHECK(frame.size() >= 4);
      CHECK(frame.size() <= kMaxFrameSize);
      (void)parse_reply(kRead17, frame);  // whatever it says, it must not read out of bounds
    }
  }
}
