// Frames: encoding and decoding against every verified vector, the manual's errata, and
// random frames.
#include <doctest/doctest.h>

#include <random>

#include "rieker/codec.h"
#include "rieker/crc16.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate::rieker;
using test::hex;

TEST_CASE("every verified frame encodes byte for byte and decodes back") {
  for (const auto& vector : test::verified_vectors()) {
    CAPTURE(vector.meaning);
    CHECK(encode(vector.frame) == hex(vector.wire));
    const auto decoded = decode(hex(vector.wire));
    REQUIRE(decoded.has_value());
    CHECK(*decoded == vector.frame);
  }
}

TEST_CASE("the Change Lock example's CRC E414 is wrong for address 101: it is 1810") {
  CHECK(decode(hex("0065 0000 000A 05 0100BC614E E414")).error() == DecodeError::bad_crc);
  // E414 belongs to the same frame sent to address 100.
  CHECK(decode(hex("0064 0000 000A 05 0100BC614E E414")).has_value());
  const Frame unlock{0x0065, 0, 10, hex("01 00BC614E")};
  CHECK(encode(unlock) == hex("0065 0000 000A 05 0100BC614E 1810"));
}

TEST_CASE("the Set Baud example's CRC 50CF is wrong: the frame as shown has 9BD4") {
  CHECK(decode(hex("0065 0000 0026 01 08 50CF")).error() == DecodeError::bad_crc);
  CHECK(encode(Frame{0x0065, 0, 38, {0x08}}) == hex("0065 0000 0026 01 08 9BD4"));
  // No value of the data byte gives 50CF: the example's CRC belongs to no baud code.
  for (int code = 0; code <= 255; ++code) {
    const auto body = hex("0065 0000 0026 01");
    auto with_code = body;
    with_code.push_back(static_cast<std::uint8_t>(code));
    CHECK(crc16(with_code) != 0x50CF);
  }
}

TEST_CASE("the firmware reply's CRC CC1E is pasted from the ACK: the real one is B6C2") {
  CHECK(decode(hex("0000 0065 001C 07 52657620412E38 CC1E")).error() == DecodeError::bad_crc);
  const auto decoded = decode(hex("0000 0065 001C 07 52657620412E38 B6C2"));
  REQUIRE(decoded.has_value());
  CHECK(decoded->data == test::ascii("Rev A.8"));
}

TEST_CASE("an ACK shown with an extra 00 data byte under DL 00 is a length mismatch") {
  // DL rules: the manual's "0000 0065 0000 00 00 CC1E" is 10 bytes for a 9-byte frame.
  CHECK(decode(hex("0000 0065 0000 00 00 CC1E")).error() == DecodeError::length_mismatch);
  CHECK(decode(hex("0000 0065 0000 00 CC1E")).has_value());
}

TEST_CASE("decode rejects short frames, length mismatches and bad CRCs") {
  CHECK(decode({}).error() == DecodeError::too_short);
  CHECK(decode(hex("0000 0065 0000 00 CC")).error() == DecodeError::too_short);
  // DL says 2 bytes, one is there.
  CHECK(decode(hex("0065 0000 0002 02 00 F727")).error() == DecodeError::length_mismatch);
  CHECK(decode(hex("0065 0000 0002 02 00DF F726")).error() == DecodeError::bad_crc);
  CHECK(std::string(to_string(DecodeError::bad_crc)) == "bad CRC");
}

TEST_CASE("changing any one byte of a verified frame makes it undecodable") {
  // CRC16 catches every burst of up to 16 bits; a changed DL breaks the length instead.
  for (const auto& vector : test::verified_vectors()) {
    const auto wire = hex(vector.wire);
    for (std::size_t i = 0; i < wire.size(); ++i) {
      for (std::uint8_t flip : {0x01, 0x80, 0xFF}) {
        auto damaged = wire;
        damaged[i] ^= flip;
        CAPTURE(vector.meaning);
        CAPTURE(i);
        CHECK_FALSE(decode(damaged).has_value());
      }
    }
  }
}

TEST_CASE("encode then decode is the identity on random frames") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> word(0, 0xFFFF);
  std::uniform_int_distribution<int> length(0, 255);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int trial = 0; trial < 2000; ++trial) {
    Frame frame{static_cast<std::uint16_t>(word(rng)), static_cast<std::uint16_t>(word(rng)),
                static_cast<std::uint16_t>(word(rng)), {}};
    frame.data.resize(static_cast<std::size_t>(trial < 256 ? trial : length(rng)));
    for (auto& b : frame.data) b = static_cast<std::uint8_t>(byte(rng));
    const auto wire = encode(frame);
    REQUIRE(wire.size() == kMinFrameSize + frame.data.size());
    REQUIRE(wire[6] == frame.data.size());
    const auto decoded = decode(wire);
    REQUIRE(decoded.has_value());
    REQUIRE(*decoded == frame);
  }
}

TEST_CASE("the largest frame is 264 bytes") {
  const Frame frame{1, 0, 5, std::vector<std::uint8_t>(255, 0xAA)};
  const auto wire = encode(frame);
  CHECK(wire.size() == kMaxFrameSize);
  CHECK(wire.size() == 264);
  CHECK(decode(wire).has_value());
}

TEST_CASE("baud codes map to the manual's table and back") {
  const std::uint32_t table[] = {9600, 38400, 115200, 125000, 128000, 250000, 19200, 62500};
  for (int code = 1; code <= 8; ++code) {
    CAPTURE(code);
    CHECK(baud_for_code(code) == table[code - 1]);
    CHECK(code_for_baud(table[code - 1]) == code);
  }
  CHECK_FALSE(baud_for_code(0));
  CHECK_FALSE(baud_for_code(9));
  CHECK_FALSE(code_for_baud(57600));
}

TEST_CASE("the default baud code is 4 (125000), not the 3 the text says") {
  CHECK(kDefaultBaudCode == 4);
  CHECK(baud_for_code(kDefaultBaudCode) == 125000u);
}

TEST_CASE("every function that changes the sensor needs lock level 1, reads do not") {
  for (Function f : {Function::set_address, Function::restart, Function::set_zero_to_value,
                     Function::set_zero_to_angle, Function::set_baud, Function::set_filter}) {
    CHECK(needs_unlock(f));
  }
  for (Function f : {Function::get_address, Function::check_address, Function::get_angle,
                     Function::change_lock, Function::get_firmware, Function::get_lock_level,
                     Function::get_serial}) {
    CHECK_FALSE(needs_unlock(f));
  }
}

TEST_CASE("function names cover the 15 user functions and nothing else") {
  int named = 0;
  for (int id = 0; id <= 0xFFFF; ++id) {
    if (function_name(static_cast<std::uint16_t>(id))) ++named;
  }
  CHECK(named == 15);
  CHECK(std::string(function_name(5)) == "get angle");
  CHECK(function_name(6) == nullptr);
}
