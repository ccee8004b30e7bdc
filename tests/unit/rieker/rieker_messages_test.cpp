// Typed requests and replies: the builders against the verified vectors, their argument
// checks, and the reply parsers.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>

#include "rieker/codec.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate::rieker;
using test::hex;

namespace {

const Route kSensor101{101, 0};

std::vector<std::uint8_t> wire(const RequestResult& request) {
  REQUIRE(request.has_value());
  return encode(*request);
}

}  // namespace

TEST_CASE("request builders produce the verified frames") {
  CHECK(wire(set_address_request(kSensor101, 223)) == hex("0065 0000 0002 02 00DF F727"));
  CHECK(wire(get_address_request({kBroadcastAddress, 0})) == hex("FFFC 0000 0003 00 C31B"));
  CHECK(wire(check_address_request({223, 0})) == hex("00DF 0000 0004 00 AF11"));
  CHECK(wire(get_angle_request(kSensor101, AngleType::x_and_y)) ==
        hex("0065 0000 0005 01 04 5425"));
  CHECK(wire(restart_request(kSensor101)) == hex("0065 0000 0010 00 3504"));
  CHECK(wire(set_zero_to_value_request(kSensor101, Axis::x, 0.0f)) ==
        hex("0065 0000 0019 05 01 00000000 995A"));
  CHECK(wire(set_zero_to_angle_request(kSensor101, ZeroPersistence::permanent)) ==
        hex("0065 0000 001A 01 01 91D4"));
  CHECK(wire(get_firmware_request(kSensor101)) == hex("0065 0000 001C 00 3501"));
  CHECK(wire(get_lock_level_request(kSensor101)) == hex("0065 0000 001E 00 5500"));
  CHECK(wire(get_serial_request(kSensor101)) == hex("0065 0000 0025 00 6513"));
  CHECK(wire(set_filter_request(kSensor101, 2)) == hex("0065 0000 0029 01 02 9F64"));
}

TEST_CASE("request builders correct the manual's errata") {
  // Password 12345678 = 0x00BC614E, big-endian after the level; CRC 1810, not E414.
  CHECK(wire(change_lock_request(kSensor101, LockLevel::unlocked)) ==
        hex("0065 0000 000A 05 01 00BC614E 1810"));
  CHECK(wire(set_baud_request(kSensor101, 8)) == hex("0065 0000 0026 01 08 9BD4"));
}

TEST_CASE("request builders lay out their data big-endian") {
  CHECK(wire(set_zero_to_value_request({1, 7}, Axis::y, 180.0f)) ==
        encode(Frame{1, 7, 25, hex("02 43340000")}));
  CHECK(wire(change_lock_request({1, 0}, LockLevel::locked, 1)) ==
        encode(Frame{1, 0, 10, hex("00 00000001")}));
  CHECK(wire(set_address_request({1, 0}, 65000)) == encode(Frame{1, 0, 2, hex("FDE8")}));
}

TEST_CASE("request builders refuse bad arguments before encoding anything") {
  CHECK_FALSE(set_address_request(kSensor101, 0).has_value());
  CHECK_FALSE(set_address_request(kSensor101, 65001).has_value());
  CHECK_FALSE(set_address_request(kSensor101, -1).has_value());
  CHECK_FALSE(set_address_request(kSensor101, 0xFFFC).has_value());
  CHECK_FALSE(set_baud_request(kSensor101, 0).has_value());
  CHECK_FALSE(set_baud_request(kSensor101, 9).has_value());
  CHECK_FALSE(set_filter_request(kSensor101, 0).has_value());
  CHECK_FALSE(set_filter_request(kSensor101, 7).has_value());
  CHECK_FALSE(get_angle_request(kSensor101, AngleType{0}).has_value());
  CHECK_FALSE(get_angle_request(kSensor101, AngleType{5}).has_value());
  CHECK_FALSE(change_lock_request(kSensor101, LockLevel{2}).has_value());
  CHECK_FALSE(set_zero_to_value_request(kSensor101, Axis{3}, 0.0f).has_value());
  CHECK_FALSE(set_zero_to_value_request(kSensor101, Axis::x, NAN).has_value());
  CHECK_FALSE(
      set_zero_to_value_request(kSensor101, Axis::x, std::numeric_limits<float>::infinity())
          .has_value());
  CHECK_FALSE(set_zero_to_value_request(kSensor101, Axis::x, 400.0f).has_value());
  CHECK_FALSE(set_zero_to_angle_request(kSensor101, ZeroPersistence{2}).has_value());
}

TEST_CASE("request builders refuse addresses outside the protocol's ranges") {
  CHECK_FALSE(get_serial_request({0, 1}).has_value());      // sensors are 1..65000
  CHECK_FALSE(get_serial_request({65001, 0}).has_value());
  CHECK_FALSE(get_serial_request({101, 65501}).has_value());  // masters are 0..65500
  CHECK_FALSE(get_serial_request({101, 101}).has_value());  // the master must differ
  CHECK(get_serial_request({kBroadcastAddress, 0}).has_value());
  CHECK(get_serial_request({65000, 65500}).has_value());
  const auto error = set_filter_request(kSensor101, 9);
  CHECK(error.error().message == "filter response 9 is outside 1..6");
}

TEST_CASE("an ACK parses and a NAK gives its code") {
  CHECK(parse_ack(*decode(hex("0000 0065 0000 00 CC1E"))).has_value());
  const auto refused = parse_ack(make_nak(0, 101, NakCode::wrong_lock_level));
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().kind == ReplyError::Kind::nak);
  CHECK(refused.error().nak_code == 4);
  CHECK(describe(refused.error()) == "NAK 4 (wrong lock level)");
  const auto odd = parse_ack(Frame{0, 101, 1, {9}});
  CHECK(odd.error().nak_code == 9);
  CHECK(describe(odd.error()) == "NAK 9 (unknown NAK code)");
}

TEST_CASE("a reply of another function or length is refused with a typed error") {
  const auto other = parse_ack(*decode(hex("0000 0065 001E 01 01 5EEC")));
  CHECK(other.error().kind == ReplyError::Kind::unexpected_function);
  CHECK(other.error().function == 30);
  CHECK(describe(other.error()) == "unexpected reply: get lock level");
  const auto short_angle = parse_angle_reply(Frame{0, 101, 5, hex("BF4B1C00")},
                                             AngleType::x_and_y);
  CHECK(short_angle.error().kind == ReplyError::Kind::wrong_length);
  CHECK(short_angle.error().data_length == 4);
  CHECK(parse_ack(Frame{0, 101, 0, {0}}).error().kind == ReplyError::Kind::wrong_length);
  CHECK(parse_ack(Frame{0, 101, 1, {}}).error().kind == ReplyError::Kind::wrong_length);
  CHECK(parse_serial_reply(Frame{0, 101, 37, test::ascii("12345")}).error().kind ==
        ReplyError::Kind::wrong_length);
  CHECK(parse_lock_level_reply(Frame{0, 101, 30, {2}}).error().kind ==
        ReplyError::Kind::bad_data);
}

TEST_CASE("the verified replies parse to their values") {
  CHECK(parse_address_reply(*decode(hex("0000 00DF 0003 02 00DF 73F3"))).value() == 223);
  const auto angles = parse_angle_reply(
      *decode(hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8")), AngleType::x_and_y);
  REQUIRE(angles.has_value());
  CHECK(angles->x == -0.79339599609375f);
  CHECK(angles->y == 18.44384765625f);
  CHECK(parse_lock_level_reply(*decode(hex("0000 0065 001E 01 01 5EEC"))).value() ==
        LockLevel::unlocked);
  CHECK(parse_serial_reply(*decode(hex("0000 0065 0025 0A 39363232383520202020 DF6D")))
            .value() == "962285");
  CHECK(parse_firmware_reply(*decode(hex("0000 0065 001C 07 52657620412E38 B6C2"))).value() ==
        "Rev A.8");
}

TEST_CASE("a one-axis angle reply fills the axis that was asked for") {
  const Frame reply{0, 101, 5, hex("41938D00")};
  CHECK(parse_angle_reply(reply, AngleType::single_axis)->x == 18.44384765625f);
  CHECK(parse_angle_reply(reply, AngleType::x)->x == 18.44384765625f);
  CHECK_FALSE(parse_angle_reply(reply, AngleType::x)->y.has_value());
  CHECK(parse_angle_reply(reply, AngleType::y)->y == 18.44384765625f);
  CHECK_FALSE(parse_angle_reply(reply, AngleType::y)->x.has_value());
}

TEST_CASE("reply builders produce the verified replies") {
  CHECK(encode(make_ack(0, 101)) == hex("0000 0065 0000 00 CC1E"));
  CHECK(encode(make_ack(0, 223)) == hex("0000 00DF 0000 00 D43B"));
  CHECK(encode(make_address_reply(0, 223)) == hex("0000 00DF 0003 02 00DF 73F3"));
  const float angles[] = {-0.79339599609375f, 18.44384765625f};
  CHECK(encode(make_angle_reply(0, 101, angles)) ==
        hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8"));
  CHECK(encode(make_lock_level_reply(0, 101, LockLevel::unlocked)) ==
        hex("0000 0065 001E 01 01 5EEC"));
  CHECK(encode(make_serial_reply(0, 101, "962285")) ==
        hex("0000 0065 0025 0A 39363232383520202020 DF6D"));
  CHECK(encode(make_firmware_reply(0, 101, "Rev A.8")) ==
        hex("0000 0065 001C 07 52657620412E38 B6C2"));
  CHECK(make_firmware_reply(0, 101, "Rev A.8 and more").data == test::ascii("Rev A.8"));
  CHECK(make_nak(0, 101, NakCode::busy) == Frame{0, 101, 1, {5}});
}

TEST_CASE("a reply belongs to a request when it comes back from the addressed sensor") {
  const Frame request = *get_serial_request({101, 7});
  CHECK(is_reply_to(make_ack(7, 101), request));
  CHECK_FALSE(is_reply_to(make_ack(7, 102), request));
  CHECK_FALSE(is_reply_to(make_ack(0, 101), request));
  const Frame broadcast = *get_address_request({kBroadcastAddress, 7});
  CHECK(is_reply_to(make_address_reply(7, 223), broadcast));
}

TEST_CASE("a reply belongs to a request only with the request's function, ACK or NAK") {
  const Frame request = *get_serial_request({101, 7});
  CHECK(is_reply_to(make_serial_reply(7, 101, "962285"), request));
  CHECK(is_reply_to(make_nak(7, 101, NakCode::busy), request));
  // From the right sensor, but the answer to another query (a late one, say).
  CHECK_FALSE(is_reply_to(make_firmware_reply(7, 101, "Rev A.8"), request));
  CHECK_FALSE(is_reply_to(make_angle_reply(7, 101, std::array{1.0f}), request));
}
