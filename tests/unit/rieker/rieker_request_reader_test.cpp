// What the control socket reads from a command's Rieker request and its reply, for the audit
// trail (rieker/request_reader.h), from the verified frames.
#include <doctest/doctest.h>

#include "rieker/codec.h"
#include "rieker/request_reader.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::rieker;
using tiltgate::rieker::test::hex;

TEST_CASE("a Rieker request that changes the sensor is read with its function and data") {
  const auto filter = read_request(hex("0065 0000 0029 01 02 9F64"));
  REQUIRE(filter);
  CHECK(filter->address == 101);
  CHECK(filter->may_change);
  CHECK(filter->function == "function 41 (set filter response)");
  CHECK(filter->data == "02");
  const auto moved = read_request(hex("0065 0000 0002 02 00DF F727"));
  REQUIRE(moved);
  CHECK(moved->may_change);
  CHECK(moved->data == "00DF");
  CHECK(read_request(hex("0065 0000 0010 00 3504"))->may_change);  // restart
  CHECK(read_request(hex("0065 0000 001A 01 01 91D4"))->may_change);  // zero, permanent
}

TEST_CASE("the Get functions, Check Address and Change Lock are not changes") {
  CHECK_FALSE(read_request(hex("0065 0000 0005 01 04 5425"))->may_change);  // get angle
  CHECK_FALSE(read_request(hex("0065 0000 0025 00 6513"))->may_change);     // get serial
  CHECK_FALSE(read_request(hex("00DF 0000 0004 00 AF11"))->may_change);     // check address
  CHECK_FALSE(read_request(hex("FFFC 0000 0003 00 C31B"))->may_change);     // get address
  const auto unlock = change_lock_request({101, 0}, LockLevel::unlocked);
  REQUIRE(unlock);
  CHECK_FALSE(read_request(encode(*unlock))->may_change);
}

TEST_CASE("a function the manual reserves for the factory may change the sensor") {
  const auto reserved = read_request(encode(Frame{101, 0, 99, {1, 2}}));
  REQUIRE(reserved);
  CHECK(reserved->may_change);
  CHECK(reserved->function == "function 99");
  CHECK(reserved->data == "0102");
}

TEST_CASE("bytes that are not one good Rieker frame are not read") {
  CHECK_FALSE(read_request(hex("0065 0000 0029 01 02 9F65")));  // CRC
  CHECK_FALSE(read_request(hex("0065 0000 0029")));
  CHECK_FALSE(read_request({}));
}

TEST_CASE("a NAK is a refusal with its code, and an ACK or a reply is none") {
  CHECK(read_refusal(encode(Frame{0, 101, 1, {4}})) == "nak 0x04");
  CHECK_FALSE(read_refusal(hex("0000 0065 0000 00 CC1E")));
  CHECK_FALSE(read_refusal(hex("0000 0065 001E 01 01 5EEC")));
  CHECK_FALSE(read_refusal(hex("0000 0065 0000 00 CC1F")));
}

TEST_CASE("a Rieker reply is read as the answer to its request: angles, identity, an ack") {
  const auto angles = read_reply(hex("0065 0000 0005 01 04 5425"),
                                 hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8"));
  CHECK(angles == "x -0.793396 deg, y 18.443848 deg");
  const auto serial_request = get_serial_request({.sensor = 101});
  REQUIRE(serial_request);
  CHECK(read_reply(encode(*serial_request), encode(make_serial_reply(0, 101, "9600101"))) ==
        "serial \"9600101\"");
  CHECK(read_reply(hex("0065 0000 0029 01 02 9F64"), encode(make_ack(0, 101))) == "ack");
  // A NAK is a refusal, not a value; a reply from another sensor answers nothing here.
  CHECK_FALSE(read_reply(hex("0065 0000 0029 01 02 9F64"), encode(make_nak(0, 101, NakCode(5)))));
  CHECK_FALSE(read_reply(hex("0065 0000 0005 01 04 5425"), encode(make_ack(0, 102))));
  CHECK_FALSE(read_reply(hex("0065 0000 0005 01 04 5426"), encode(make_ack(0, 101))));  // bad CRC
}
