// The Modbus-ASCII streaming parser and its Line adapter: whole frames, byte at a time, noise,
// cut-short frames, bad LRCs, overlong frames, and random streams with a fixed seed.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "spectron/ascii_frame_parser.h"
#include "spectron/reply_framers.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate::spectron;
using test::bytes;
using test::kDocumentFrames;

namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<AsciiFrame> drain(AsciiFrameParser& parser) {
  std::vector<AsciiFrame> frames;
  while (auto frame = parser.next()) frames.push_back(std::move(*frame));
  return frames;
}

// Feeds `stream` in chunks of 1..max_chunk bytes (max_chunk 0: all at once).
std::vector<AsciiFrame> parse(AsciiFrameParser& parser, const Bytes& stream, std::mt19937& rng,
                              std::size_t max_chunk) {
  std::vector<AsciiFrame> frames;
  std::size_t at = 0;
  while (at < stream.size()) {
    std::size_t n = stream.size() - at;
    if (max_chunk > 0) {
      n = std::min(n, std::uniform_int_distribution<std::size_t>(1, max_chunk)(rng));
    }
    parser.feed(std::span(stream).subspan(at, n));
    at += n;
    for (auto& frame : drain(parser)) frames.push_back(std::move(frame));
    REQUIRE(parser.buffered() <= kMaxFrameLength);
  }
  return frames;
}

AsciiFrame random_frame(std::mt19937& rng) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<std::size_t> length(0, 4);  // sized like real frames
  AsciiFrame frame{static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)), {}};
  frame.data.resize(length(rng));
  for (auto& b : frame.data) b = static_cast<std::uint8_t>(byte(rng));
  return frame;
}

// Random bytes that never contain ':', so they cannot start a frame.
Bytes noise(std::mt19937& rng, std::size_t count) {
  Bytes out(count);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& b : out) {
    do {
      b = static_cast<std::uint8_t>(byte(rng));
    } while (b == ':');
  }
  return out;
}

void append(Bytes& to, const Bytes& more) { to.insert(to.end(), more.begin(), more.end()); }

}  // namespace

TEST_CASE("Modbus-ASCII: the parser yields a whole frame fed at once") {
  AsciiFrameParser parser;
  CHECK(parser.feed(bytes(kDocumentFrames[0].wire)) == 1);
  CHECK(parser.next() == AsciiFrame{2, 0x68, {0x00, 0x64, 0x01, 0x63}});
  CHECK_FALSE(parser.next().has_value());
  CHECK(parser.counters().frames_ok == 1);
  CHECK(parser.counters().bytes_discarded == 0);
  CHECK(parser.buffered() == 0);
}

TEST_CASE("the parser gives the same frames fed a byte at a time as fed whole") {
  Bytes stream;
  for (const auto& example : kDocumentFrames) append(stream, bytes(example.wire));
  AsciiFrameParser whole;
  whole.feed(stream);
  AsciiFrameParser single;
  std::vector<AsciiFrame> one_by_one;
  for (std::uint8_t byte : stream) {
    single.feed(std::span(&byte, 1));
    for (auto& frame : drain(single)) one_by_one.push_back(std::move(frame));
  }
  const auto all = drain(whole);
  CHECK(all.size() == 4);
  CHECK(one_by_one == all);
}

TEST_CASE("the parser resynchronises on ':' after noise and cut-short frames") {
  AsciiFrameParser parser;
  Bytes stream = {0x00, 0xFF, 'x', '\r', '\n'};
  append(stream, bytes(":0166"));            // cut short by the next ':'
  append(stream, bytes(kDocumentFrames[2].wire));
  append(stream, bytes(":01Z6"));            // not hex: ":01Z" dropped at once, "6" is noise
  append(stream, bytes("33\r\n"));           // outside a frame: noise
  append(stream, bytes(kDocumentFrames[1].wire));
  parser.feed(stream);
  CHECK(drain(parser) == std::vector<AsciiFrame>{{1, 0x66, {}}, {2, 0x68, {}}});
  CHECK(parser.counters().malformed == 2);
  CHECK(parser.counters().lrc_errors == 0);
  CHECK(parser.counters().bytes_discarded == 5 + 5 + 4 + 1 + 4);
}

TEST_CASE("the parser rejects a bad LRC, odd digit counts and a CR without LF") {
  AsciiFrameParser parser;
  parser.feed(bytes(test::kPrintedWrite15));  // bad LRC (uppercase F)
  parser.feed(bytes(":0166333\r\n"));        // odd number of digits
  parser.feed(bytes(":016633\rX"));          // CR not followed by LF
  parser.feed(bytes(":0133\r\n"));           // too short
  CHECK(drain(parser).empty());
  CHECK(parser.counters().lrc_errors == 1);
  CHECK(parser.counters().malformed == 3);
  parser.feed(bytes(test::kLowercaseWrite15));
  CHECK(parser.next() == AsciiFrame{1, 0x68, {0x00, 0x16, 0x00, 0x0F}});
}

TEST_CASE("the parser drops an overlong frame and finds the next one") {
  AsciiFrameParser parser;
  Bytes stream = bytes(":");
  append(stream, Bytes(200, '0'));
  append(stream, bytes("\r\n"));
  append(stream, bytes(kDocumentFrames[3].wire));
  std::mt19937 rng(7);
  CHECK(parse(parser, stream, rng, 0) == std::vector<AsciiFrame>{{20, 0x69, {0x00, 0x02}}});
  CHECK(parser.counters().malformed == 1);
}

TEST_CASE("reset drops a partial frame and waiting frames") {
  AsciiFrameParser parser;
  parser.feed(bytes(kDocumentFrames[2].wire));
  parser.feed(bytes(":0166"));
  CHECK(parser.buffered() == 5);
  parser.reset();
  CHECK(parser.buffered() == 0);
  CHECK_FALSE(parser.next().has_value());
  parser.feed(bytes("33\r\n"));  // the rest of the dropped frame is noise
  CHECK_FALSE(parser.next().has_value());
}

TEST_CASE("random frames among noise are all found, in any chunking (fixed seed)") {
  std::mt19937 rng(20240611);
  for (int round = 0; round < 200; ++round) {
    Bytes stream;
    std::vector<AsciiFrame> sent;
    for (int i = 0; i < 5; ++i) {
      append(stream, noise(rng, std::uniform_int_distribution<std::size_t>(0, 20)(rng)));
      sent.push_back(random_frame(rng));
      append(stream, encode(sent.back()));
    }
    AsciiFrameParser whole;
    AsciiFrameParser chunked;
    AsciiFrameParser single;
    CHECK(parse(whole, stream, rng, 0) == sent);
    CHECK(parse(chunked, stream, rng, 7) == sent);
    CHECK(parse(single, stream, rng, 1) == sent);
  }
}

TEST_CASE("random garbage never overflows the parser and yields only frames that verify") {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> pick(0, 19);
  const std::string alphabet = ":0123456789ABCDEFabcdef\r\nxyz";
  for (int round = 0; round < 200; ++round) {
    Bytes stream;
    for (int i = 0; i < 300; ++i) {
      // Mostly frame-like characters, so that partial frames and bad LRCs are common.
      if (pick(rng) == 0) {
        append(stream, noise(rng, 1));
      } else {
        stream.push_back(static_cast<std::uint8_t>(
            alphabet[std::uniform_int_distribution<std::size_t>(0, alphabet.size() - 1)(rng)]));
      }
    }
    AsciiFrameParser parser;
    for (const auto& frame : parse(parser, stream, rng, 5)) {
      CHECK(decode(encode_text(frame)).has_value());
    }
  }
}

TEST_CASE("the reply framer takes only the reply from the expected module and command") {
  const AsciiFrame request = *ascii_read_sensor_request(1);
  AsciiReplyFramer framer(request);
  CHECK_FALSE(framer.feed(encode(make_ascii_word_reply(2, AsciiCommand::read_sensor, 5))));
  CHECK_FALSE(framer.feed(encode(make_ascii_word_reply(1, AsciiCommand::read_eeprom, 5))));
  // Our own request heard back (an echo) has the module and command of the reply: the framer
  // takes it, and the typed parse says it is no reply.
  CHECK(framer.feed(bytes(":016633\r\n")));
  REQUIRE(framer.reply().has_value());
  CHECK(parse_ascii_sensor_reply(*framer.reply(), request).error().kind ==
        ReplyError::Kind::wrong_length);
}

TEST_CASE("the reply framer counts bad LRCs and completes on the good reply after them") {
  const AsciiFrame request = *ascii_revision_request(9);
  AsciiReplyFramer framer(request);
  std::string damaged = encode_text(make_ascii_word_reply(9, AsciiCommand::revision, 0x0107));
  damaged[damaged.size() - 3] ^= 0x01;
  CHECK_FALSE(framer.feed(bytes(damaged)));
  CHECK(framer.lrc_errors() == 1);
  const Bytes good = encode(make_ascii_word_reply(9, AsciiCommand::revision, 0x0107));
  for (std::size_t i = 0; i + 1 < good.size(); ++i) {
    CHECK_FALSE(framer.feed(std::span(&good[i], 1)));
  }
  CHECK(framer.feed(std::span(&good.back(), 1)));
  CHECK(*parse_ascii_revision_reply(*framer.reply(), request) == "01.07");
  framer.reset();
  CHECK_FALSE(framer.reply().has_value());
}
