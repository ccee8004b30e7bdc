// Modbus TCP pass-through on a Modbus RTU bus (modbus_rtu/forwarding.h): the frame sent for a
// PDU, and the reply PDU relayed from the first good frame of the slave asked, exceptions and
// functions the gateway does not know included.
#include <doctest/doctest.h>

#include "driver/family.h"
#include "modbus_rtu/family.h"
#include "modbus_rtu/forwarding.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using test::framed;
using test::hex;

namespace {

std::unique_ptr<ForwardedExchange> exchange(std::uint8_t slave, std::string_view pdu) {
  const std::vector<std::uint8_t> bytes = hex(pdu);
  auto made = forward_request(slave, bytes);
  REQUIRE(made.has_value());
  return std::move(*made);
}

std::vector<std::uint8_t> concat(std::vector<std::uint8_t> a, const std::vector<std::uint8_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("RTU pass-through frames the PDU unchanged for its slave, CRC appended") {
  auto forwarded = exchange(30, "03 00 6B 00 03");
  CHECK(forwarded->request_bytes() == framed("1E 03 00 6B 00 03"));
  // A function the gateway never sends itself goes out just the same.
  CHECK(exchange(30, "08 00 00 A5 37")->request_bytes() == framed("1E 08 00 00 A5 37"));
}

TEST_CASE("RTU pass-through refuses what it has no frame for") {
  CHECK_FALSE(forward_request(0, hex("03 00 00 00 01")).has_value());  // broadcast: no reply
  CHECK_FALSE(forward_request(248, hex("03 00 00 00 01")).has_value());
  CHECK_FALSE(forward_request(30, {}).has_value());
  CHECK_FALSE(forward_request(30, std::vector<std::uint8_t>(254, 0x03)).has_value());
}

TEST_CASE("RTU pass-through relays the reply PDU without address and CRC") {
  auto forwarded = exchange(30, "03 00 6B 00 03");
  ReplyFramer& framer = forwarded->framer();
  framer.reset();
  const auto reply = framed("1E 03 06 02 2B 00 00 00 64");
  // Byte by byte, as a slow serial read delivers it.
  for (std::size_t i = 0; i + 1 < reply.size(); ++i) CHECK_FALSE(framer.feed({&reply[i], 1}));
  CHECK(framer.feed({&reply.back(), 1}));
  REQUIRE(forwarded->reply_pdu().has_value());
  CHECK(*forwarded->reply_pdu() == hex("03 06 02 2B 00 00 00 64"));
}

TEST_CASE("RTU pass-through relays a device exception unchanged") {
  auto forwarded = exchange(30, "03 01 00 00 01");
  CHECK(forwarded->framer().feed(framed("1E 83 02")));
  REQUIRE(forwarded->reply_pdu().has_value());
  CHECK(*forwarded->reply_pdu() == hex("83 02"));
}

TEST_CASE("RTU pass-through skips garbage and other slaves' frames before the reply") {
  auto forwarded = exchange(30, "11");  // report server id: length by byte count
  const auto noise = concat(hex("00 FF 1E"), framed("11 11 02 AA BB"));  // slave 17's frame
  CHECK_FALSE(forwarded->framer().feed(noise));
  CHECK(forwarded->framer().feed(framed("1E 11 03 AA BB FF")));
  REQUIRE(forwarded->reply_pdu().has_value());
  CHECK(*forwarded->reply_pdu() == hex("11 03 AA BB FF"));
}

TEST_CASE("RTU pass-through finds the end of a reply of unknown length by its CRC") {
  auto forwarded = exchange(30, "41 01 02");  // a user-defined function
  CHECK(forwarded->framer().feed(concat(framed("1E 41 09 08 07"), hex("00 00"))));
  REQUIRE(forwarded->reply_pdu().has_value());
  CHECK(*forwarded->reply_pdu() == hex("41 09 08 07"));
}

TEST_CASE("RTU pass-through has no reply PDU before the reply, and starts over on reset") {
  auto forwarded = exchange(30, "04 00 00 00 01");
  CHECK_FALSE(forwarded->reply_pdu().has_value());
  CHECK(forwarded->framer().feed(framed("1E 04 02 12 34")));
  forwarded->framer().reset();
  CHECK_FALSE(forwarded->reply_pdu().has_value());
}

TEST_CASE("the modbus-rtu and modbus-tcp protocols offer pass-through, each in its framing") {
  REQUIRE(kFamily.protocols.size() == 2);
  CHECK(kFamily.protocols[0].name == "modbus-rtu");
  const bool rtu = kFamily.protocols[0].forward == &forward_request;
  CHECK(rtu);
  CHECK(kFamily.protocols[1].name == "modbus-tcp");
  const bool mbap = kFamily.protocols[1].forward == &forward_mbap_request;
  CHECK(mbap);
}
