// What each family's reply framer tells the trace log (ReplyFramer::report): the reply exactly
// as it was on the wire, the verdict in the family's own checksum's words, and what became of
// rejected bytes, counted from the framer's last reset().
#include <doctest/doctest.h>

#include <string>
#include <string_view>
#include <vector>

#include "modbus_rtu/forwarding.h"
#include "modbus_rtu/reply_framer.h"
#include "rieker/reply_framer.h"
#include "spectron/reply_framers.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"
#include "unit/rieker/rieker_test_vectors.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate;
using Bytes = std::vector<std::uint8_t>;

namespace {

// Feeds `stream` after a reset, as the Line does at the start of an attempt.
FramerReport report_after(ReplyFramer& framer, const Bytes& stream, bool expect_reply) {
  framer.reset();
  CHECK(framer.feed(stream) == expect_reply);
  return framer.report();
}

Bytes joined(const Bytes& a, const Bytes& b) {
  Bytes out = a;
  out.insert(out.end(), b.begin(), b.end());
  return out;
}

Bytes corrupted(Bytes frame, std::size_t from_end) {
  frame[frame.size() - from_end] ^= 0x01;
  return frame;
}

// A Modbus-ASCII frame's text with its LRC over the characters as written (docs/protocols.md,
// "Dyna LRC").
std::string with_lrc(std::string_view text) {
  unsigned sum = 0;
  for (char c : text.substr(1)) sum += static_cast<unsigned char>(c);
  static constexpr char kDigits[] = "0123456789ABCDEF";
  const unsigned lrc = (0x100 - (sum & 0xFF)) & 0xFF;
  return std::string(text) + kDigits[lrc >> 4] + kDigits[lrc & 0xF] + "\r\n";
}

}  // namespace

TEST_CASE("Rieker reply framer reports the reply's bytes with \"CRC ok\"") {
  rieker::RiekerReplyFramer framer(rieker::Frame{0x0065, 0, 5, {0x04}});
  const Bytes reply = rieker::test::hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
  const FramerReport report = report_after(framer, reply, true);
  CHECK(report.reply == reply);
  CHECK(report.reply_verdict == "CRC ok");
  CHECK(report.rejected_verdict == "");
}

TEST_CASE("Rieker reply framer reports a corrupted reply as \"bad CRC\", until the next reset") {
  rieker::RiekerReplyFramer framer(rieker::Frame{0x0065, 0, 5, {0x04}});
  const Bytes reply = rieker::test::hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
  const FramerReport bad = report_after(framer, corrupted(reply, 1), false);
  CHECK(bad.reply.empty());
  CHECK(bad.rejected_verdict == "bad CRC");

  const FramerReport then_good = report_after(framer, reply, true);
  CHECK(then_good.rejected_verdict == "");
  CHECK(then_good.reply == reply);

  const FramerReport bad_then_good = report_after(framer, joined(corrupted(reply, 3), reply), true);
  CHECK(bad_then_good.reply == reply);
  CHECK(bad_then_good.rejected_verdict == "bad CRC");
}

TEST_CASE("Modbus RTU reply framer reports the reply's bytes with \"CRC ok\" and bad CRCs") {
  using modbus_rtu::test::hex;
  const auto request = modbus_rtu::read_request(17, modbus_rtu::RegisterBank::holding, 107, 3);
  REQUIRE(request.has_value());
  modbus_rtu::RtuReplyFramer framer(*request);
  const Bytes reply = hex("11 03 06 AE 41 56 52 43 40 49 AD");

  const FramerReport good = report_after(framer, reply, true);
  CHECK(good.reply == reply);
  CHECK(good.reply_verdict == "CRC ok");
  CHECK(good.rejected_verdict == "");

  const FramerReport bad = report_after(framer, corrupted(reply, 1), false);
  CHECK(bad.reply.empty());
  CHECK(bad.rejected_verdict == "bad CRC");

  const FramerReport after_noise = report_after(framer, joined(hex("00 FF"), reply), true);
  CHECK(after_noise.reply == reply);
}

TEST_CASE("Modbus RTU reply framer says when a reply with a good CRC fails its checks") {
  const auto request = modbus_rtu::read_request(17, modbus_rtu::RegisterBank::holding, 107, 3);
  REQUIRE(request.has_value());
  modbus_rtu::RtuReplyFramer framer(*request);
  const Bytes short_reply = modbus_rtu::test::framed("11 03 02 00 01");
  const FramerReport report = report_after(framer, short_reply, true);
  CHECK(report.reply == short_reply);
  CHECK(report.reply_verdict ==
        std::string("CRC ok, but ") + modbus_rtu::to_string(modbus_rtu::CodecError::bad_byte_count));
}

TEST_CASE("Modbus RTU pass-through reports the relayed reply's bytes with \"CRC ok\"") {
  using modbus_rtu::test::hex;
  const Bytes pdu = hex("03 00 6B 00 03");
  auto exchange = modbus_rtu::forward_request(17, pdu);
  REQUIRE(exchange.has_value());
  ReplyFramer& framer = (*exchange)->framer();
  const Bytes reply = hex("11 03 06 AE 41 56 52 43 40 49 AD");

  const FramerReport bad = report_after(framer, corrupted(reply, 2), false);
  CHECK(bad.rejected_verdict == "bad CRC");
  const FramerReport good = report_after(framer, reply, true);
  CHECK(good.reply == reply);
  CHECK(good.reply_verdict == "CRC ok");
  CHECK(good.rejected_verdict == "");
}

TEST_CASE("Spectron Modbus-ASCII reply framer reports the reply as received with \"LRC ok\"") {
  using spectron::test::bytes;
  const auto request = spectron::ascii_read_sensor_request(1);
  REQUIRE(request.has_value());
  spectron::AsciiReplyFramer framer(*request);
  // Lower-case hex digits: the report keeps them, since the LRC was over them.
  const std::string reply = with_lrc(":016600af");

  const FramerReport good = report_after(framer, bytes(reply), true);
  CHECK(good.reply == bytes(reply));
  CHECK(good.reply_verdict == "LRC ok");
  CHECK(good.rejected_verdict == "");

  std::string damaged = reply;
  damaged[damaged.size() - 3] = damaged[damaged.size() - 3] == '0' ? '1' : '0';
  const FramerReport bad = report_after(framer, bytes(damaged), false);
  CHECK(bad.reply.empty());
  CHECK(bad.rejected_verdict == "bad LRC");

  const FramerReport cut = report_after(framer, bytes(":0166\r\n"), false);
  CHECK(cut.rejected_verdict == "malformed frame");
}

TEST_CASE("Spectron 9-bit reply framer reports the line with its CR LF and no checksum") {
  using spectron::test::bytes;
  spectron::NineBitReplyFramer framer;
  const FramerReport good = report_after(framer, bytes("1001\r\n"), true);
  CHECK(good.reply == bytes("1001\r\n"));
  CHECK(good.reply_verdict == "CR LF, no checksum");
  CHECK(good.rejected_verdict == "");

  const FramerReport overlong = report_after(framer, bytes(std::string(300, '7') + "\r\n"), false);
  CHECK(overlong.rejected_verdict == "overlong line");
}

TEST_CASE("a framer that does not report gives the Line nothing to name") {
  class Plain : public ReplyFramer {
   public:
    void reset() override {}
    bool feed(std::span<const std::uint8_t>) override { return true; }
  } plain;
  const FramerReport report = plain.report();
  CHECK(report.reply.empty());
  CHECK(report.reply_verdict.empty());
  CHECK(report.rejected_verdict.empty());
}
