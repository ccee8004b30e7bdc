// The streaming parser: whole frames, byte at a time, garbage, false starts that claim long
// frames, corrupted frames, and random streams.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "rieker/frame_parser.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate::rieker;
using test::hex;

namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<Frame> drain(RiekerFrameParser& parser) {
  std::vector<Frame> frames;
  while (auto frame = parser.next()) frames.push_back(std::move(*frame));
  return frames;
}

// Feeds `stream` in chunks of 1..max_chunk bytes (max_chunk 0: all at once).
std::vector<Frame> parse(RiekerFrameParser& parser, const Bytes& stream, std::mt19937& rng,
                         std::size_t max_chunk) {
  std::vector<Frame> frames;
  std::size_t at = 0;
  while (at < stream.size()) {
    std::size_t n = stream.size() - at;
    if (max_chunk > 0) n = std::min(n, std::uniform_int_distribution<std::size_t>(1, max_chunk)(rng));
    parser.feed(std::span(stream).subspan(at, n));
    at += n;
    for (auto& frame : drain(parser)) frames.push_back(std::move(frame));
    REQUIRE(parser.buffered() <= kMaxFrameSize);
  }
  return frames;
}

Bytes random_bytes(std::mt19937& rng, std::size_t count) {
  Bytes bytes(count);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(byte(rng));
  return bytes;
}

Frame random_frame(std::mt19937& rng) {
  std::uniform_int_distribution<int> word(0, 0xFFFF);
  std::uniform_int_distribution<std::size_t> length(0, 12);  // sized like real replies
  Frame frame{static_cast<std::uint16_t>(word(rng)), static_cast<std::uint16_t>(word(rng)),
              static_cast<std::uint16_t>(word(rng)), random_bytes(rng, length(rng))};
  return frame;
}

Frame take(RiekerFrameParser& parser) {
  auto frame = parser.next();
  REQUIRE(frame.has_value());
  return std::move(*frame);
}

void append(Bytes& to, const Bytes& bytes) { to.insert(to.end(), bytes.begin(), bytes.end()); }

bool contains(const Bytes& haystack, const Bytes& needle) {
  return std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end()) !=
         haystack.end();
}

}  // namespace

TEST_CASE("the parser yields a whole frame fed at once") {
  RiekerFrameParser parser;
  CHECK(parser.feed(hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8")) == 1);
  const auto frame = parser.next();
  REQUIRE(frame.has_value());
  CHECK(frame->data == hex("BF4B1C00 41938D00"));
  CHECK_FALSE(parser.next().has_value());
  CHECK(parser.counters().frames_ok == 1);
  CHECK(parser.counters().crc_errors == 0);
  CHECK(parser.buffered() == 0);
}

TEST_CASE("the parser yields a frame fed one byte at a time, only at its last byte") {
  RiekerFrameParser parser;
  const Bytes wire = hex("0000 0065 0025 0A 39363232383520202020 DF6D");
  for (std::size_t i = 0; i + 1 < wire.size(); ++i) {
    CHECK(parser.feed(std::span(&wire[i], 1)) == 0);
  }
  CHECK(parser.feed(std::span(&wire.back(), 1)) == 1);
  CHECK(take(parser).data == test::ascii("962285    "));
}

TEST_CASE("the parser yields every verified frame from one stream, in order") {
  RiekerFrameParser parser;
  Bytes stream;
  for (const auto& vector : test::verified_vectors()) append(stream, hex(vector.wire));
  parser.feed(stream);
  const auto frames = drain(parser);
  REQUIRE(frames.size() == test::verified_vectors().size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    CHECK(frames[i] == test::verified_vectors()[i].frame);
  }
  CHECK(parser.counters().bytes_discarded == 0);
}

TEST_CASE("a valid frame after garbage is found and the garbage counted as discarded") {
  RiekerFrameParser parser;
  Bytes stream = hex("13 37 42");
  append(stream, hex("0000 00DF 0000 00 D43B"));
  CHECK(parser.feed(stream) == 1);
  CHECK(take(parser) == Frame{0, 0xDF, 0, {}});
  CHECK(parser.counters().bytes_discarded == 3);
  CHECK(parser.counters().crc_errors == 1);  // one bad stretch where a frame was due
}

TEST_CASE("a short reply right after a false header claiming DL 255 is found at once") {
  // The garbage reads as DEST 0000, SRC 00DF, FUNCT 0005, DL FF: a parser that trusted it
  // would wait for 264 bytes.
  const Bytes garbage = hex("0000 00DF 0005 FF");
  const Bytes reply = hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
  for (bool byte_at_a_time : {false, true}) {
    CAPTURE(byte_at_a_time);
    RiekerFrameParser parser;
    parser.feed(garbage);
    CHECK(parser.buffered() == garbage.size());
    std::size_t ready = 0;
    if (byte_at_a_time) {
      for (std::uint8_t b : reply) ready = parser.feed(std::span(&b, 1));
    } else {
      ready = parser.feed(reply);
    }
    REQUIRE(ready == 1);
    CHECK(take(parser).data == hex("BF4B1C00 41938D00"));
    CHECK(parser.counters().bytes_discarded == garbage.size());
    CHECK(parser.buffered() == 0);
  }
}

TEST_CASE("a corrupted frame counts one CRC error and the next good frame is found") {
  RiekerFrameParser parser;
  Bytes damaged = hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
  damaged[9] ^= 0x10;
  parser.feed(damaged);
  CHECK_FALSE(parser.next().has_value());
  CHECK(parser.counters().crc_errors == 1);
  parser.feed(hex("0000 0065 0000 00 CC1E"));
  CHECK(take(parser) == Frame{0, 0x65, 0, {}});
  CHECK(parser.counters().crc_errors == 1);
  CHECK(parser.counters().frames_ok == 1);
}

TEST_CASE("a frame that fails its CRC where a frame was due is kept for a NAK 0") {
  RiekerFrameParser parser;
  parser.feed(hex("0065 0000 0029 01 02 9F65"));  // set filter, CRC off by one
  const auto damaged = parser.take_crc_failure();
  REQUIRE(damaged.has_value());
  CHECK(*damaged == Frame{0x65, 0, 41, {0x02}});
  CHECK_FALSE(parser.take_crc_failure().has_value());
}

TEST_CASE("the manual's ACK with an extra 00 byte under DL 00 yields no frame") {
  // DL rules: the first nine bytes end in 00 CC, not the CRC CC1E.
  RiekerFrameParser parser;
  CHECK(parser.feed(hex("0000 0065 0000 00 00 CC1E")) == 0);
  CHECK(parser.counters().crc_errors == 1);
}

TEST_CASE("reset drops buffered bytes and waiting frames") {
  RiekerFrameParser parser;
  parser.feed(hex("0000 0065 0000 00 CC1E 0000 00DF"));
  CHECK(parser.buffered() == 4);
  parser.reset();
  CHECK(parser.buffered() == 0);
  CHECK_FALSE(parser.next().has_value());
  CHECK(parser.counters().bytes_discarded == 4);
  parser.feed(hex("0000 00DF 0000 00 D43B"));
  CHECK(parser.next().has_value());
}

TEST_CASE("random garbage in random chunks never yields a frame that was not on the wire") {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 10; ++trial) {
    RiekerFrameParser parser;
    const Bytes garbage = random_bytes(rng, 10000);
    std::size_t in_frames = 0;
    for (const Frame& frame : parse(parser, garbage, rng, 64)) {
      // Anything found must be a CRC-valid frame present in the input as encoded.
      CHECK(contains(garbage, encode(frame)));
      in_frames += encode(frame).size();
    }
    CHECK(parser.buffered() < kMaxFrameSize);
    // Every byte is accounted for: in a frame, discarded, or still buffered.
    CHECK(in_frames + parser.counters().bytes_discarded + parser.buffered() == garbage.size());
  }
}

TEST_CASE("the parser's buffer stays bounded whatever arrives") {
  RiekerFrameParser parser;
  // All 0xFF: every offset claims DL 255, the longest possible frame.
  const Bytes worst(5000, 0xFF);
  parser.feed(worst);
  CHECK(parser.buffered() < kMaxFrameSize);
  CHECK(parser.counters().bytes_discarded + parser.buffered() == worst.size());
  std::mt19937 rng(99);
  parse(parser, random_bytes(rng, 5000), rng, 300);
  CHECK(parser.buffered() < kMaxFrameSize);
}

TEST_CASE("valid frames embedded in garbage are all found, in order") {
  std::mt19937 rng(42);
  std::uniform_int_distribution<std::size_t> gap(0, 40);
  for (int trial = 0; trial < 50; ++trial) {
    Bytes stream;
    std::vector<Frame> sent;
    for (int i = 0; i < 20; ++i) {
      append(stream, random_bytes(rng, gap(rng)));
      sent.push_back(random_frame(rng));
      append(stream, encode(sent.back()));
    }
    RiekerFrameParser parser;
    CAPTURE(trial);
    CHECK(parse(parser, stream, rng, 16) == sent);
  }
}

TEST_CASE("byte-at-a-time feeding finds what whole feeding finds") {
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> gap(0, 30);
  for (int trial = 0; trial < 30; ++trial) {
    Bytes stream;
    for (int i = 0; i < 15; ++i) {
      append(stream, random_bytes(rng, gap(rng)));
      append(stream, encode(random_frame(rng)));
    }
    RiekerFrameParser whole;
    RiekerFrameParser bytewise;
    RiekerFrameParser chunked;
    const auto from_whole = parse(whole, stream, rng, 0);
    CHECK(parse(bytewise, stream, rng, 1) == from_whole);
    CHECK(parse(chunked, stream, rng, 25) == from_whole);
    for (const RiekerFrameParser* other : {&bytewise, &chunked}) {
      CHECK(other->counters().frames_ok == whole.counters().frames_ok);
      CHECK(other->counters().crc_errors == whole.counters().crc_errors);
      CHECK(other->counters().bytes_discarded == whole.counters().bytes_discarded);
      CHECK(other->buffered() == whole.buffered());
    }
  }
}
