// What the control socket reads from a command's Modbus request and its reply, as an RTU frame
// or an MBAP frame, for the audit trail (modbus_rtu/request_reader.h).
#include <doctest/doctest.h>

#include "modbus_rtu/request_reader.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using tiltgate::modbus_rtu::test::framed;
using tiltgate::modbus_rtu::test::hex;

TEST_CASE("an RTU write is a change with its function and data, and a read is not") {
  const auto write = read_rtu_request(framed("11 06 0001 0003"));
  REQUIRE(write);
  CHECK(write->address == 17);
  CHECK(write->may_change);
  CHECK(write->function == "function 06");
  CHECK(write->data == "00010003");
  CHECK(read_rtu_request(framed("11 10 0001 0001 02 0005"))->may_change);
  CHECK(read_rtu_request(framed("11 08 0001 0000"))->may_change);  // diagnostics may restart
  CHECK(read_rtu_request(framed("11 41 00"))->may_change);         // a profile's own function
  CHECK_FALSE(read_rtu_request(framed("11 03 0000 000A"))->may_change);
  CHECK_FALSE(read_rtu_request(framed("11 2B 0E 01 00"))->may_change);
}

TEST_CASE("bytes that are not one RTU frame with a good CRC are not read") {
  std::vector<std::uint8_t> broken = framed("11 06 0001 0003");
  broken.back() ^= 1;
  CHECK_FALSE(read_rtu_request(broken));
  CHECK_FALSE(read_rtu_request(hex("11 06")));
}

TEST_CASE("an RTU exception reply is a refusal with its code") {
  CHECK(read_rtu_refusal(framed("11 86 02")) == "nak 0x02");
  CHECK_FALSE(read_rtu_refusal(framed("11 06 0001 0003")));
}

TEST_CASE("an MBAP request and its exception reply are read the same way") {
  const auto write = read_mbap_request(hex("0007 0000 0006 FF 06 0001 0003"));
  REQUIRE(write);
  CHECK(write->address == 255);
  CHECK(write->may_change);
  CHECK(write->data == "00010003");
  CHECK_FALSE(read_mbap_request(hex("0007 0000 0006 FF 03 0000 000A"))->may_change);
  CHECK_FALSE(read_mbap_request(hex("0007 0000 0009 FF 06 0001 0003")));  // the length
  CHECK_FALSE(read_mbap_request(hex("0007 0001 0006 FF 06 0001 0003")));  // the protocol id
  CHECK(read_mbap_refusal(hex("0007 0000 0003 FF 86 02")) == "nak 0x02");
  CHECK_FALSE(read_mbap_refusal(hex("0007 0000 0006 FF 06 0001 0003")));
}

TEST_CASE("a Modbus reply is read as the answer to its request: values, bits, a write") {
  CHECK(read_rtu_reply(framed("01 03 0000 0002"), framed("01 03 04 0004 0001")) == "values 4, 1");
  CHECK(read_rtu_reply(framed("01 02 0000 0003"), framed("01 02 01 05")) == "bits 1 0 1");
  CHECK(read_rtu_reply(framed("01 06 0001 0003"), framed("01 06 0001 0003")) == "written");
  CHECK_FALSE(read_rtu_reply(framed("01 03 0000 0002"), framed("01 83 02")));  // a refusal
  CHECK_FALSE(read_rtu_reply(framed("01 03 0000 0002"), framed("02 03 04 0004 0001")));  // not its
  CHECK(read_mbap_reply(hex("0007 0000 0006 FF 03 0000 0002"), hex("0007 0000 0007 FF 03 04 0004 0001")) ==
        "values 4, 1");
  CHECK_FALSE(read_mbap_reply(hex("0007 0000 0006 FF 03 0000 0002"),
                              hex("0008 0000 0007 FF 03 04 0004 0001")));  // another transaction
}
