// The Modbus-ASCII-style codec: the note's examples, the LRC over characters (and its letter
// case), decoding errors, request builders and reply parsing.
#include <doctest/doctest.h>

#include "spectron/ascii_codec.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate::spectron;
using test::kDocumentFrames;

namespace {

AsciiFrame built(const AsciiRequestResult& request) {
  REQUIRE_MESSAGE(request.has_value(), request.error().message);
  return *request;
}

AsciiFrame decoded(std::string_view text) {
  auto frame = decode(text);
  REQUIRE_MESSAGE(frame.has_value(), to_string(frame.error()));
  return *frame;
}

}  // namespace

TEST_CASE("the LRC is the two's complement of the sum of the characters, not of the bytes") {
  CHECK(lrc("02680064 0163") != 0x9C);  // a stray space changes it
  CHECK(lrc("026800640163") == 0x9C);
  CHECK(lrc("0268") == 0x30);
  CHECK(lrc("0166") == 0x33);
  CHECK(lrc("14690002") == 0x6A);
  // The standard Modbus LRC over the binary bytes 02 68 00 64 01 63 would be 0xCE.
  CHECK(lrc("026800640163") != 0xCE);
  CHECK(lrc("") == 0x00);
}

TEST_CASE("every example frame of the note verifies as printed") {
  for (const auto& example : kDocumentFrames) {
    CAPTURE(example.meaning);
    CHECK(decode(example.wire).has_value());
  }
}

TEST_CASE("the note's examples decode to what they say") {
  CHECK(decoded(kDocumentFrames[0].wire) == AsciiFrame{2, 0x68, {0x00, 0x64, 0x01, 0x63}});
  CHECK(decoded(kDocumentFrames[1].wire) == AsciiFrame{2, 0x68, {}});
  CHECK(decoded(kDocumentFrames[2].wire) == AsciiFrame{1, 0x66, {}});
  CHECK(decoded(kDocumentFrames[3].wire) == AsciiFrame{20, 0x69, {0x00, 0x02}});
}

TEST_CASE("the request builders reproduce the note's examples") {
  CHECK(encode_text(built(ascii_write_eeprom_request(2, 100, 355))) == kDocumentFrames[0].wire);
  CHECK(encode_text(make_ascii_ack(2, AsciiCommand::write_eeprom)) == kDocumentFrames[1].wire);
  CHECK(encode_text(built(ascii_read_sensor_request(1))) == kDocumentFrames[2].wire);
  CHECK(encode_text(built(ascii_read_eeprom_request(20, 2))) == kDocumentFrames[3].wire);
}

TEST_CASE("the LRC depends on the letter case actually sent") {
  // "Write 15 to location 22 in module address 1" as printed only checks with a lowercase f.
  CHECK(decode(test::kPrintedWrite15).error() == AsciiDecodeError::bad_lrc);
  CHECK(decoded(test::kLowercaseWrite15) == AsciiFrame{1, 0x68, {0x00, 0x16, 0x00, 0x0F}});
  CHECK(decoded(test::kUppercaseWrite15) == AsciiFrame{1, 0x68, {0x00, 0x16, 0x00, 0x0F}});
  // The encoder sends uppercase, with the LRC of what it sends.
  CHECK(encode_text(built(ascii_write_eeprom_request(1, 22, 15))) == test::kUppercaseWrite15);
  CHECK(lrc("01680016000f") == 0x74);
  CHECK(lrc("01680016000F") == 0x94);
}

TEST_CASE("hex is read in either case, the LRC digits too") {
  // The same frame in lowercase has another LRC; each verifies over its own characters.
  const std::string upper = encode_text(AsciiFrame{0xAB, 0x6A, {0xCD, 0xEF}});
  std::string lower = ":ab6acdef";
  const std::uint8_t sum = lrc("ab6acdef");
  const char digits[] = "0123456789abcdef";
  lower += digits[sum >> 4];
  lower += digits[sum & 0x0F];
  lower += "\r\n";
  CHECK(decoded(upper) == AsciiFrame{0xAB, 0x6A, {0xCD, 0xEF}});
  CHECK(decoded(lower) == AsciiFrame{0xAB, 0x6A, {0xCD, 0xEF}});
  CHECK(upper != lower);
}

TEST_CASE("decode says why a frame is not one") {
  CHECK(decode("016633\r\n").error() == AsciiDecodeError::no_start);
  CHECK(decode(":016633").error() == AsciiDecodeError::no_end);
  CHECK(decode(":016633\n").error() == AsciiDecodeError::no_end);
  CHECK(decode(":0166333\r\n").error() == AsciiDecodeError::odd_digits);
  CHECK(decode(":01G633\r\n").error() == AsciiDecodeError::not_hex);
  CHECK(decode(":01 6633\r\n").error() == AsciiDecodeError::not_hex);
  CHECK(decode(":0133\r\n").error() == AsciiDecodeError::too_short);
  CHECK(decode(":\r\n").error() == AsciiDecodeError::too_short);
  CHECK(decode(":016634\r\n").error() == AsciiDecodeError::bad_lrc);
  CHECK(decode(std::string(":") + std::string(70, '0') + "\r\n").error() ==
        AsciiDecodeError::too_long);
  CHECK(decode("").error() == AsciiDecodeError::no_start);
}

TEST_CASE("encode then decode gives the frame back") {
  for (int data = 0; data <= 12; ++data) {
    AsciiFrame frame{static_cast<std::uint8_t>(17 * data + 1), 0x69, {}};
    for (int i = 0; i < data; ++i) frame.data.push_back(static_cast<std::uint8_t>(i * 37 + data));
    CHECK(decoded(encode_text(frame)) == frame);
    CHECK(encode(frame) == test::bytes(encode_text(frame)));
  }
}

TEST_CASE("request builders check the address, location and value") {
  CHECK(encode_text(built(ascii_reset_request(7))) == ":07652E\r\n");
  CHECK(built(ascii_read_temperature_request(250)).command == 0x67);
  CHECK(built(ascii_revision_request(1)).command == 0x6A);
  CHECK_FALSE(ascii_read_sensor_request(0).has_value());
  CHECK(ascii_read_sensor_request(251).error().message ==
        "module address 251 is out of range 1..250");
  CHECK_FALSE(ascii_read_eeprom_request(1, 3).has_value());     // odd
  CHECK_FALSE(ascii_read_eeprom_request(1, 40).has_value());    // not in the map
  CHECK_FALSE(ascii_read_eeprom_request(1, 282).has_value());
  CHECK(ascii_read_eeprom_request(1, 280).has_value());
  CHECK_FALSE(ascii_write_eeprom_request(1, 6, 65536).has_value());
  CHECK_FALSE(ascii_write_eeprom_request(1, 6, -1).has_value());
  CHECK(built(ascii_write_eeprom_request(1, 6, 65535)).data ==
        std::vector<std::uint8_t>{0x00, 0x06, 0xFF, 0xFF});
}

TEST_CASE("replies are matched to their request and read as words (assumption A6)") {
  const AsciiFrame read = built(ascii_read_sensor_request(1));
  CHECK(*parse_ascii_sensor_reply(make_ascii_word_reply(1, AsciiCommand::read_sensor, 1001),
                                  read) == 1001);
  CHECK(*parse_ascii_sensor_reply(decoded(":0166FFFF1B\r\n"), read) == -1);
  CHECK(parse_ascii_sensor_reply(make_ascii_word_reply(2, AsciiCommand::read_sensor, 1), read)
            .error()
            .kind == ReplyError::Kind::wrong_address);
  CHECK(parse_ascii_sensor_reply(make_ascii_word_reply(1, AsciiCommand::read_temperature, 1), read)
            .error()
            .kind == ReplyError::Kind::wrong_command);
  CHECK(parse_ascii_sensor_reply(make_ascii_ack(1, AsciiCommand::read_sensor), read).error().kind ==
        ReplyError::Kind::wrong_length);

  const AsciiFrame temperature = built(ascii_read_temperature_request(3));
  CHECK(*parse_ascii_temperature_reply(
            make_ascii_word_reply(3, AsciiCommand::read_temperature, 0xFF38), temperature) == -200);
  const AsciiFrame eeprom = built(ascii_read_eeprom_request(3, 4));
  CHECK(*parse_ascii_eeprom_reply(make_ascii_word_reply(3, AsciiCommand::read_eeprom, 54321),
                                  eeprom) == 54321);
  const AsciiFrame revision = built(ascii_revision_request(3));
  CHECK(*parse_ascii_revision_reply(make_ascii_word_reply(3, AsciiCommand::revision, 0x0107),
                                    revision) == "01.07");
  CHECK(revision_text(0xAB0F) == "AB.0F");
}

TEST_CASE("reset and write are acknowledged by an echo of address and command") {
  const AsciiFrame write = built(ascii_write_eeprom_request(2, 100, 355));
  CHECK(parse_ascii_ack(decoded(kDocumentFrames[1].wire), write).has_value());
  const AsciiFrame reset = built(ascii_reset_request(2));
  CHECK(parse_ascii_ack(make_ascii_ack(2, AsciiCommand::reset), reset).has_value());
  CHECK(parse_ascii_ack(make_ascii_ack(2, AsciiCommand::write_eeprom), reset).error().kind ==
        ReplyError::Kind::wrong_command);
  CHECK(parse_ascii_ack(make_ascii_word_reply(2, AsciiCommand::reset, 0), reset).error().kind ==
        ReplyError::Kind::wrong_length);
  // A read is not answered by an echo.
  CHECK_FALSE(parse_ascii_ack(make_ascii_ack(1, AsciiCommand::read_sensor),
                              built(ascii_read_sensor_request(1)))
                  .has_value());
  CHECK(describe(parse_ascii_ack(make_ascii_ack(3, AsciiCommand::reset), reset).error()) ==
        "reply from another module: expected module 2, got 3");
}

TEST_CASE("word_at reads big-endian words and stops at the data's end") {
  const AsciiFrame frame{1, 0x68, {0x00, 0x16, 0x00, 0x0F, 0x12}};
  CHECK(word_at(frame, 0) == 22);
  CHECK(word_at(frame, 1) == 15);
  CHECK_FALSE(word_at(frame, 2).has_value());
  CHECK(ascii_command_name(0x6A) == std::string("send revision"));
  CHECK(ascii_command_name(0x03) == nullptr);
}
