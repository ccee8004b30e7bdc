// Each protocol's passive framer (ProtocolDescriptor::passive_framer) on its own: what the
// bytes in front of a listener are, read as a request or as a reply, with and without the
// request the reply would answer.
#include <doctest/doctest.h>

#include <string_view>
#include <vector>

#include "driver/family.h"
#include "modbus_rtu/passive_framer.h"
#include "rieker/passive_framer.h"
#include "spectron/passive_framers.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Kind = PassiveCut::Kind;

Bytes text(std::string_view characters) { return Bytes(characters.begin(), characters.end()); }

Bytes first(const Bytes& bytes, std::size_t count) {
  return Bytes(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(count));
}

const Bytes kNone;

}  // namespace

TEST_CASE("a Rieker frame is whole once its DL's bytes are in, its CRC saying good or bad") {
  const Bytes request = rieker::test::hex("0065 0000 0005 01 04 5425");
  CHECK(rieker::passive_frame(first(request, 6), PassiveRole::request, kNone).kind ==
        Kind::need_more);
  CHECK(rieker::passive_frame(first(request, 9), PassiveRole::request, kNone).kind ==
        Kind::need_more);
  const PassiveCut whole = rieker::passive_frame(request, PassiveRole::request, kNone);
  CHECK(whole.kind == Kind::frame);
  CHECK(whole.length == request.size());
  CHECK(whole.intact);
  CHECK(whole.verdict == "CRC ok");
  Bytes broken = request;
  broken[7] ^= 0x01;
  const PassiveCut bad = rieker::passive_frame(broken, PassiveRole::request, kNone);
  CHECK(bad.kind == Kind::frame);
  CHECK_FALSE(bad.intact);
  CHECK(bad.verdict == "bad CRC");
}

TEST_CASE("a Rieker frame that is not addressed as the reply to the request is no reply") {
  const Bytes request = rieker::test::hex("0065 0000 0005 01 04 5425");
  const Bytes reply = rieker::test::hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8");
  const Bytes other = rieker::test::hex("0000 00DF 0000 00 D43B");  // ACK from 223
  CHECK(rieker::passive_frame(reply, PassiveRole::reply, request).intact);
  CHECK(rieker::passive_frame(other, PassiveRole::reply, request).kind == Kind::not_a_start);
  CHECK(rieker::passive_frame(request, PassiveRole::reply, request).kind == Kind::not_a_start);
  CHECK(rieker::passive_frame(other, PassiveRole::reply, kNone).intact);  // no request known
}

TEST_CASE("a Modbus RTU frame's length follows its function code, a reply is the slave asked's") {
  const Bytes read = modbus_rtu::test::hex("11 03 00 6B 00 03 76 87");
  const Bytes reply = modbus_rtu::test::hex("11 03 06 AE 41 56 52 43 40 49 AD");
  CHECK(modbus_rtu::passive_frame(first(read, 5), PassiveRole::request, kNone).kind ==
        Kind::need_more);
  CHECK(modbus_rtu::passive_frame(read, PassiveRole::request, kNone).length == 8);
  CHECK(modbus_rtu::passive_frame(first(reply, 10), PassiveRole::reply, read).kind ==
        Kind::need_more);
  const PassiveCut answered = modbus_rtu::passive_frame(reply, PassiveRole::reply, read);
  CHECK(answered.kind == Kind::frame);
  CHECK(answered.length == reply.size());
  CHECK(answered.intact);
  // Another slave's frame, or a function the request did not ask, is not its reply.
  const Bytes other = modbus_rtu::test::framed("12 03 02 00 01");
  CHECK(modbus_rtu::passive_frame(other, PassiveRole::reply, read).kind == Kind::not_a_start);
  CHECK(modbus_rtu::passive_frame(other, PassiveRole::reply, kNone).intact);
  // Slave 0 broadcasts: nothing answers.
  const Bytes broadcast = modbus_rtu::test::framed("00 06 00 01 00 03");
  CHECK(modbus_rtu::passive_frame(broadcast, PassiveRole::reply, broadcast).kind ==
        Kind::not_a_start);
  // No request starts with an address above 247 or function 0.
  CHECK(modbus_rtu::passive_frame(Bytes{0xF8}, PassiveRole::request, kNone).kind ==
        Kind::not_a_start);
  CHECK(modbus_rtu::passive_frame(Bytes{0x11, 0x00}, PassiveRole::request, kNone).kind ==
        Kind::not_a_start);
}

TEST_CASE("a Modbus RTU frame of a function the length rule does not know ends at its CRC") {
  const Bytes unusual = modbus_rtu::test::framed("11 41 01 02 03");
  CHECK(modbus_rtu::passive_frame(first(unusual, 5), PassiveRole::request, kNone).kind ==
        Kind::need_more);
  const PassiveCut cut = modbus_rtu::passive_frame(unusual, PassiveRole::request, kNone);
  CHECK(cut.kind == Kind::frame);
  CHECK(cut.length == unusual.size());
}

TEST_CASE("a Modbus-ASCII frame runs from ':' to CR LF, its LRC checked as heard") {
  const Bytes write = text(":0268006401639C\r\n");
  const Bytes ack = text(":026830\r\n");
  CHECK(spectron::ascii_passive_frame(text(":0268"), PassiveRole::request, kNone).kind ==
        Kind::need_more);
  CHECK(spectron::ascii_passive_frame(text("x:0268"), PassiveRole::request, kNone).kind ==
        Kind::not_a_start);
  CHECK(spectron::ascii_passive_frame(text(":02G8"), PassiveRole::request, kNone).kind ==
        Kind::not_a_start);
  CHECK(spectron::ascii_passive_frame(text(":02:0268"), PassiveRole::request, kNone).kind ==
        Kind::not_a_start);  // a new start cuts the frame short
  Bytes both = write;  // two frames heard at once: the first is cut
  both.insert(both.end(), ack.begin(), ack.end());
  const PassiveCut whole = spectron::ascii_passive_frame(both, PassiveRole::request, kNone);
  CHECK(whole.kind == Kind::frame);
  CHECK(whole.length == write.size());
  CHECK(whole.verdict == "LRC ok");
  CHECK(spectron::ascii_passive_frame(ack, PassiveRole::reply, write).intact);
  const PassiveCut bad =
      spectron::ascii_passive_frame(text(":026831\r\n"), PassiveRole::reply, write);
  CHECK(bad.kind == Kind::frame);
  CHECK(bad.verdict == "bad LRC");
  // Module 1's ack is not module 2's reply.
  CHECK(spectron::ascii_passive_frame(text(":016831\r\n"), PassiveRole::reply, write).kind ==
        Kind::not_a_start);
}

TEST_CASE("a 9-bit request is an address byte and a command the module knows, up to CR LF") {
  const PassiveCut read =
      spectron::nine_bit_passive_frame(text("\x05" "A\r\n"), PassiveRole::request, kNone);
  CHECK(read.kind == Kind::frame);
  CHECK(read.length == 4);
  CHECK(read.address_bytes == 1);
  CHECK(read.verdict == "CR LF, no checksum");
  CHECK(spectron::nine_bit_passive_frame(text("\r" "E34,2501\r\n"), PassiveRole::request, kNone)
            .length == 11);  // the address byte may be any value, CR included
  CHECK(spectron::nine_bit_passive_frame(text("\x05" "Z\r\n"), PassiveRole::request, kNone).kind ==
        Kind::not_a_start);
  CHECK(spectron::nine_bit_passive_frame(text("\x05" "A"), PassiveRole::request, kNone).kind ==
        Kind::need_more);
}

TEST_CASE("a 9-bit reply is a line of text, and a read's reply one number") {
  const Bytes read = text("\x05" "A\r\n");
  CHECK(spectron::nine_bit_passive_frame(text("1001\r\n"), PassiveRole::reply, read).length == 6);
  CHECK(spectron::nine_bit_passive_frame(text("DYNA\r\n"), PassiveRole::reply, read).kind ==
        Kind::not_a_start);
  CHECK(spectron::nine_bit_passive_frame(text("DYNA 1.07\r\n"), PassiveRole::reply,
                                         text("\x05" "F\r\n"))
            .kind == Kind::frame);
  CHECK(spectron::nine_bit_passive_frame(text("\x01" "10\r\n"), PassiveRole::reply, kNone).kind ==
        Kind::not_a_start);
}

TEST_CASE("every serial protocol can be listened to, and a TCP one cannot") {
  for (const FamilyDescriptor* family : registered_families())
    for (const ProtocolDescriptor& protocol : family->protocols) {
      CAPTURE(protocol.name);
      CHECK((protocol.passive_framer == nullptr) == protocol.devices_speak_tcp);
    }
}
