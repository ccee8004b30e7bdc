// The passive decoder on each protocol's verified frames (docs/protocols.md), fed as a tty
// would deliver them: whole, several in one read, or a byte at a time; with garbage, a bad
// checksum, silences and unanswered requests. Times are made up: the decoder reads no clock.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <vector>

#include "capture/passive_decoder.h"
#include "modbus_rtu/passive_framer.h"
#include "rieker/passive_framer.h"
#include "spectron/ascii_codec.h"
#include "spectron/passive_framers.h"
#include "unit/capture/heard_recorder.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"
#include "unit/rieker/rieker_test_vectors.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;
using Strings = std::vector<std::string>;

const Clock::time_point kStart = Clock::time_point{} + 1h;
const std::chrono::system_clock::time_point kWallStart =
    std::chrono::system_clock::from_time_t(1'700'000'000);

// Character times: 125000 baud 8N1 (a Rieker factory bus), 19200 8E1 (the Modbus default),
// 28800 8E1 (the Dyna note's example rate).
constexpr std::chrono::nanoseconds kRiekerCharacter = 80us;
constexpr std::chrono::nanoseconds kRtuCharacter{572'917};
constexpr std::chrono::nanoseconds kDynaCharacter{381'944};

// A decoder and what it handed on; bytes are heard at times after kStart.
struct HeardLine {
  explicit HeardLine(PassiveFramer framer, std::chrono::nanoseconds character = kRiekerCharacter)
      : decoder(options(framer, character), recorder) {}

  static PassiveDecoderOptions options(PassiveFramer framer, std::chrono::nanoseconds character) {
    PassiveDecoderOptions o;
    o.framer = framer;
    o.character_time = character;
    o.steady_anchor = kStart;
    o.wall_anchor = kWallStart;
    return o;
  }

  void hear(Clock::duration at, const Bytes& bytes) { decoder.heard(bytes, kStart + at); }
  // Each byte in a read of its own, one character time after the one before.
  void hear_bytewise(Clock::duration at, const Bytes& bytes, std::chrono::nanoseconds character) {
    for (std::size_t i = 0; i < bytes.size(); ++i)
      decoder.heard(Bytes{bytes[i]}, kStart + at + i * character);
  }
  void quiet_until(Clock::duration at) { decoder.advance(kStart + at); }

  Strings verdicts() const { return recorder.verdicts(); }
  const PassiveDecoderCounters& counters() const { return decoder.counters(); }

  test::HeardRecorder recorder;
  PassiveDecoder decoder;
};

Bytes operator+(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// docs/protocols.md, "Rieker verified frames".
const Bytes kGetAngles = rieker::test::hex("0065 0000 0005 01 04 5425");
const Bytes kAngles = rieker::test::hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
const Bytes kGetLock = rieker::test::hex("0065 0000 001E 00 5500");
const Bytes kLockLevel = rieker::test::hex("0000 0065 001E 01 01 5EEC");
const Bytes kGetSerial = rieker::test::hex("0065 0000 0025 00 6513");
const Bytes kSerial = rieker::test::hex("0000 0065 0025 0A 39363232383520202020 DF6D");

// The Modbus application protocol's example (read 3 registers from 0x6B of slave 17), its
// reply and exception, and a write whose reply echoes it (tests/unit/modbus_rtu).
const Bytes kRtuRead = modbus_rtu::test::hex("11 03 00 6B 00 03 76 87");
const Bytes kRtuReadReply = modbus_rtu::test::hex("11 03 06 AE 41 56 52 43 40 49 AD");
const Bytes kRtuException = modbus_rtu::test::hex("11 83 02 C1 34");
const Bytes kRtuWrite = modbus_rtu::test::hex("11 06 00 01 00 03 9A 9B");

Bytes text(std::string_view characters) { return Bytes(characters.begin(), characters.end()); }

}  // namespace

TEST_CASE("a Rieker request and its reply are cut and paired, each at its first byte's time") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetAngles);
  line.hear(3ms, kAngles);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok"});
  REQUIRE(line.recorder.frames.size() == 2);
  const HeardFrame& request = line.recorder.frames[0];
  const HeardFrame& reply = line.recorder.frames[1];
  CHECK(request.frame.bytes == kGetAngles);
  CHECK(request.frame.direction == FrameDirection::to_devices);
  CHECK(request.frame.time == kWallStart);
  CHECK(reply.frame.bytes == kAngles);
  CHECK(reply.frame.direction == FrameDirection::from_devices);
  CHECK(reply.frame.time == kWallStart + 3ms);
  CHECK(reply.answers == request.number);
  REQUIRE(line.recorder.exchanges.size() == 1);
  CHECK(line.recorder.exchanges[0].request.frame.bytes == kGetAngles);
  REQUIRE(line.recorder.exchanges[0].reply.has_value());
  CHECK(line.recorder.exchanges[0].reply->frame.bytes == kAngles);
  CHECK(line.counters().replies_paired == 1);
  CHECK(line.counters().frames == 2);
}

TEST_CASE("two frames in one read are cut apart, the second dated by the characters before it") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetLock + kLockLevel);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok"});
  REQUIRE(line.recorder.frames.size() == 2);
  CHECK(line.recorder.frames[1].frame.bytes == kLockLevel);
  CHECK(line.recorder.frames[1].frame.time - kWallStart == kGetLock.size() * kRiekerCharacter);
  CHECK(line.recorder.exchanges.size() == 1);
}

TEST_CASE("a frame that arrives a byte at a time is one frame") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetSerial);
  line.hear_bytewise(2ms, kSerial, kRiekerCharacter);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok"});
  REQUIRE(line.recorder.frames.size() == 2);
  CHECK(line.recorder.frames[1].frame.bytes == kSerial);
  CHECK(line.counters().garbled == 0);
}

TEST_CASE("a reply with a bad CRC is flagged, and still ends its request's wait") {
  HeardLine line(rieker::passive_frame);
  Bytes broken = kAngles;
  broken.back() ^= 0x01;
  line.hear(0ms, kGetAngles);
  line.hear(2ms, broken);
  line.quiet_until(10ms);  // once the silence shows no good frame starts inside it
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, bad CRC"});
  REQUIRE(line.recorder.exchanges.size() == 1);
  REQUIRE(line.recorder.exchanges[0].reply.has_value());
  CHECK_FALSE(line.recorder.exchanges[0].reply->intact);
  CHECK(line.counters().bad_checks == 1);
}

TEST_CASE("garbage between frames is one garbled frame, and the frames around it are whole") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetLock);
  line.hear(2ms, kLockLevel);
  // Noise as the bus turns round, then the master's next request 1 ms later: no silence.
  line.hear(3500us, rieker::test::hex("FF 00 FF"));
  line.hear(4500us, kGetAngles);
  line.hear(6ms, kAngles);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok", "garbled",
                                   "request, CRC ok", "reply, CRC ok"});
  CHECK(line.recorder.frames[2].frame.bytes == rieker::test::hex("FF 00 FF"));
  CHECK(line.recorder.exchanges.size() == 2);
  CHECK(line.counters().garbled_bytes == 3);
}

TEST_CASE("noise stuck to the front of a frame is garbled, the frame behind it found") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, Bytes{0x42} + kGetAngles + kAngles);
  CHECK(line.verdicts() == Strings{"garbled", "request, CRC ok", "reply, CRC ok"});
  CHECK(line.recorder.frames[0].frame.bytes == Bytes{0x42});
}

TEST_CASE("a request the master repeats gets no reply, and the repeat is a request") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetAngles);
  line.hear(100ms, kGetAngles);  // the master's retry after its time-out
  line.hear(102ms, kAngles);
  CHECK(line.verdicts() ==
        Strings{"request, CRC ok, no reply", "request, CRC ok", "reply, CRC ok"});
  REQUIRE(line.recorder.exchanges.size() == 2);
  CHECK_FALSE(line.recorder.exchanges[0].reply.has_value());
  CHECK(line.recorder.exchanges[1].reply.has_value());
  CHECK(line.counters().no_replies == 1);
  CHECK(line.counters().requests == 2);
}

TEST_CASE("a request still unanswered when the reply window closes gets no reply") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetAngles);
  line.quiet_until(900ms);
  CHECK(line.recorder.frames.empty());  // handed on once its pairing is known
  const auto deadline = line.decoder.next_deadline();
  REQUIRE(deadline.has_value());
  CHECK(*deadline > kStart + 1s);
  CHECK(*deadline < kStart + 1001ms);
  line.quiet_until(1001ms);
  CHECK(line.verdicts() == Strings{"request, CRC ok, no reply"});
  REQUIRE(line.recorder.exchanges.size() == 1);
  CHECK_FALSE(line.recorder.exchanges[0].reply.has_value());
  CHECK_FALSE(line.decoder.next_deadline().has_value());
}

TEST_CASE("a partial frame cut by a silence is garbled, and the next frame is read afresh") {
  HeardLine line(rieker::passive_frame);
  const Bytes half(kGetAngles.begin(), kGetAngles.begin() + 5);
  line.hear(0ms, half);
  line.quiet_until(1ms);
  CHECK(line.recorder.frames.empty());  // 1 ms is no silence yet
  line.quiet_until(3ms);
  CHECK(line.verdicts() == Strings{"garbled"});
  line.hear(5ms, kGetAngles);
  line.hear(7ms, kAngles);
  CHECK(line.verdicts() == Strings{"garbled", "request, CRC ok", "reply, CRC ok"});
}

TEST_CASE("a silence inside a frame cuts it: both parts are garbled") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetAngles);
  line.hear(2ms, Bytes(kAngles.begin(), kAngles.begin() + 12));
  line.hear(10ms, Bytes(kAngles.begin() + 12, kAngles.end()));  // 8 ms later
  line.quiet_until(1100ms);
  CHECK(line.verdicts() == Strings{"request, CRC ok, no reply", "garbled", "garbled"});
  CHECK(line.counters().garbled_bytes == kAngles.size());
}

TEST_CASE("listening that ends while a request waits hands it on without an exchange") {
  HeardLine line(rieker::passive_frame);
  line.hear(0ms, kGetAngles);
  line.decoder.finish();
  CHECK(line.verdicts() == Strings{"request, CRC ok, listening ended"});
  CHECK(line.recorder.exchanges.empty());
  CHECK(line.counters().no_replies == 0);
}

TEST_CASE("Modbus RTU reads, exceptions and echoed writes are paired with their requests") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  line.hear(0ms, kRtuRead);
  line.hear(10ms, kRtuReadReply);
  line.hear(50ms, kRtuRead);
  line.hear(60ms, kRtuException);
  line.hear(100ms, kRtuWrite);
  line.hear(110ms, kRtuWrite);  // the reply echoes the request
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok", "request, CRC ok",
                                   "reply, CRC ok", "request, CRC ok", "reply, CRC ok"});
  CHECK(line.recorder.exchanges.size() == 3);
  CHECK(line.counters().replies_paired == 3);
}

TEST_CASE("Modbus RTU frames a byte at a time, and two in one read, are cut the same") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  line.hear_bytewise(0ms, kRtuRead, kRtuCharacter);
  line.hear_bytewise(10ms, kRtuReadReply, kRtuCharacter);
  line.hear(50ms, kRtuRead + kRtuReadReply);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok", "request, CRC ok",
                                   "reply, CRC ok"});
}

TEST_CASE("a Modbus RTU reply with a bad CRC is flagged as the reply") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  Bytes broken = kRtuReadReply;
  broken[4] ^= 0x10;
  line.hear(0ms, kRtuRead);
  line.hear(10ms, broken);
  line.quiet_until(20ms);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, bad CRC"});
}

TEST_CASE("a Modbus RTU request repeated without a reply is two requests, not a pair") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  line.hear(0ms, kRtuRead);
  line.hear(200ms, kRtuRead);
  line.hear(210ms, kRtuReadReply);
  CHECK(line.verdicts() ==
        Strings{"request, CRC ok, no reply", "request, CRC ok", "reply, CRC ok"});
}

TEST_CASE("a Modbus RTU reply after the reply window answers no request heard") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  line.hear(0ms, kRtuRead);
  line.hear(1500ms, kRtuReadReply);
  CHECK(line.verdicts() ==
        Strings{"request, CRC ok, no reply", "reply to no request heard, CRC ok"});
  CHECK(line.counters().unpaired_replies == 1);
}

TEST_CASE("Modbus RTU garbage between exchanges is garbled") {
  HeardLine line(modbus_rtu::passive_frame, kRtuCharacter);
  line.hear(0ms, kRtuRead);
  line.hear(10ms, kRtuReadReply);
  line.hear(15ms, modbus_rtu::test::hex("FF FE"));
  line.hear(30ms, kRtuWrite);
  line.hear(40ms, kRtuWrite);
  CHECK(line.verdicts() == Strings{"request, CRC ok", "reply, CRC ok", "garbled",
                                   "request, CRC ok", "reply, CRC ok"});
}

TEST_CASE("Modbus-ASCII frames of the Dyna note are paired, a bad LRC flagged, noise garbled") {
  HeardLine line(spectron::ascii_passive_frame, kDynaCharacter);
  const Bytes write = text(spectron::test::kDocumentFrames[0].wire);  // :0268006401639C
  const Bytes write_ack = text(spectron::test::kDocumentFrames[1].wire);  // :026830
  const Bytes read_sensor = text(spectron::test::kDocumentFrames[2].wire);  // :016633
  // A6's example: module 1 reads 1001 counts.
  const Bytes counts = spectron::encode(
      spectron::make_ascii_word_reply(1, spectron::AsciiCommand::read_sensor, 1001));
  Bytes bad_lrc = counts;  // its last LRC digit changed for another hex digit
  char& digit = reinterpret_cast<char&>(bad_lrc[bad_lrc.size() - 3]);
  digit = digit == '0' ? '1' : '0';
  line.hear(0ms, write);
  line.hear(20ms, write_ack);
  line.hear(60ms, Bytes{0x7F, 0x00});
  line.hear(100ms, read_sensor);
  line.hear_bytewise(110ms, counts, kDynaCharacter);
  line.hear(200ms, read_sensor + bad_lrc);  // both in one read
  line.quiet_until(300ms);
  CHECK(line.verdicts() == Strings{"request, LRC ok", "reply, LRC ok", "garbled",
                                   "request, LRC ok", "reply, LRC ok", "request, LRC ok",
                                   "reply, bad LRC"});
}

TEST_CASE("9-bit Dyna requests are cut by their form, the address byte marked, replies by CR LF") {
  HeardLine line(spectron::nine_bit_passive_frame, kDynaCharacter);
  line.hear(0ms, text("\x01" "A\r\n"));
  line.hear(5ms, text("1001\r\n"));
  line.hear(50ms, text("\x01" "E34,2501\r\n"));
  line.hear(55ms, text("\r\n"));
  CHECK(line.verdicts() == Strings{"request, CR LF, no checksum", "reply, CR LF, no checksum",
                                   "request, CR LF, no checksum", "reply, CR LF, no checksum"});
  REQUIRE(line.recorder.frames.size() == 4);
  CHECK(line.recorder.frames[0].frame.address_bytes == 1);
  CHECK(line.recorder.frames[1].frame.address_bytes == 0);
  CHECK(line.counters().replies_paired == 2);
}

TEST_CASE("a 9-bit request to a printable address after an unanswered read is not its reply") {
  HeardLine line(spectron::nine_bit_passive_frame, kDynaCharacter);
  line.hear(0ms, text("\x01" "A\r\n"));
  line.hear(100ms, text("AA\r\n"));  // module 0x41's read: not the number a read answers
  line.hear(105ms, text("-12\r\n"));
  CHECK(line.verdicts() == Strings{"request, CR LF, no checksum, no reply",
                                   "request, CR LF, no checksum", "reply, CR LF, no checksum"});
}

TEST_CASE("the silence that ends a partial frame is 3.5 characters, never under 2 ms") {
  CHECK(listen_silence(kRtuCharacter) == std::chrono::nanoseconds(2'005'209));  // 19200 8E1
  CHECK(listen_silence(std::chrono::nanoseconds(1'145'833)) == 4'010'415ns);  // 9600 8E1
  CHECK(listen_silence(kRiekerCharacter) == 2ms);                             // 125000 8N1
}

TEST_CASE("a read's first byte is dated back by the wire time of its bytes") {
  const auto read_done = kStart + 10ms;
  CHECK(first_byte_time(read_done, 10, 80us, kStart) == kStart + 9200us);
  // Never before the last byte of the read before it.
  CHECK(first_byte_time(read_done, 10, 80us, kStart + 9500us) == kStart + 9500us);
}

TEST_CASE("every byte heard comes out in exactly one frame, the frames in wire order") {
  // Frames, noise, cut frames, in reads of every size from 1 to 13 bytes, with silences.
  Bytes half_angles(kAngles.begin(), kAngles.begin() + 11);
  const Bytes stream = kGetAngles + kAngles + Bytes{0x13, 0x37} + kGetLock + half_angles +
                       kGetSerial + kSerial + kGetLock + kGetLock + kLockLevel;
  for (std::size_t read = 1; read <= 13; ++read) {
    CAPTURE(read);
    HeardLine line(rieker::passive_frame);
    auto at = Clock::duration::zero();
    for (std::size_t i = 0; i < stream.size(); i += read) {
      const std::size_t n = std::min(read, stream.size() - i);
      line.hear(at, Bytes(stream.begin() + i, stream.begin() + i + n));
      at += n * kRiekerCharacter + (i % 3 == 0 ? 3ms : 0ms);
    }
    line.decoder.finish();
    Bytes heard;
    std::uint64_t number = 0;
    for (const HeardFrame& frame : line.recorder.frames) {
      CHECK(frame.number > number);
      number = frame.number;
      heard.insert(heard.end(), frame.frame.bytes.begin(), frame.frame.bytes.end());
    }
    CHECK(heard == stream);
  }
}
