// The 9-bit addressing codec: the note's reset, read and write examples, the request builders'
// checks, the sensor side's reading of a command, reply parsing, and the reply line parser.
#include <doctest/doctest.h>

#include <random>

#include "spectron/nine_bit_codec.h"
#include "spectron/reply_framers.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate::spectron;
using test::bytes;

namespace {

using Bytes = std::vector<std::uint8_t>;

NineBitRequest built(const NineBitRequestResult& request) {
  REQUIRE_MESSAGE(request.has_value(), request.error().message);
  return *request;
}

NineBitCommandLine command(std::string_view body) {
  auto line = parse_nine_bit_body(body);
  REQUIRE_MESSAGE(line.has_value(), line.error());
  return *line;
}

std::vector<std::string> lines(NineBitLineParser& parser) {
  std::vector<std::string> out;
  while (auto line = parser.next()) out.push_back(std::move(*line));
  return out;
}

}  // namespace

TEST_CASE("the note's reset example: address 00, 48 ('0'), CR, LF") {
  const NineBitRequest reset = nine_bit_reset_request(0);
  CHECK(reset.address == 0x00);
  CHECK(reset.body == Bytes{48, '\r', '\n'});
  CHECK(wire_bytes(reset) == Bytes{0x00, 48, 0x0D, 0x0A});
  CHECK(command("0").command == NineBitCommand::reset);
}

TEST_CASE("the note's read sensor example: address 00, 65 ('A'), CR, LF, the unit returns 1001") {
  const NineBitRequest read = nine_bit_read_sensor_request(0);
  CHECK(wire_bytes(read) == Bytes{0x00, 65, 0x0D, 0x0A});
  // "Unit Returns 1001": "10" "01" CR LF.
  NineBitLineParser parser;
  CHECK(parser.feed(bytes("1001\r\n")) == 1);
  const auto line = parser.next();
  REQUIRE(line.has_value());
  const auto number = parse_nine_bit_number(*line);
  REQUIRE(number.has_value());
  CHECK(number->value == 1001);
  CHECK(number->text == "1001");
}

TEST_CASE("the note's write example: address 00, 69 ('E'), 34, 44 (','), 2501, CR, LF") {
  const Bytes body = {69, '3', '4', 44, '2', '5', '0', '1', '\r', '\n'};
  const NineBitCommandLine line = command(std::string_view(
      reinterpret_cast<const char*>(body.data()), body.size() - 2));
  CHECK(line.command == NineBitCommand::write_eeprom);
  CHECK(line.location == 34);
  CHECK(line.value == 2501);
  // The builder writes the same shape, but only to locations of the memory map: 34 is not in
  // it (2..22, 100..280), so the gateway never sends the note's example as it stands.
  CHECK(built(nine_bit_write_eeprom_request(0, 22, 2501)).body == bytes("E22,2501\r\n"));
  CHECK(nine_bit_write_eeprom_request(0, 34, 2501).error().message ==
        "EEPROM location 34 is not in the memory map (2..22, 100..280)");
}

TEST_CASE("every delimiter the note allows is accepted both ways") {
  for (char delimiter : {' ', ',', ':', '\t'}) {
    CAPTURE(static_cast<int>(delimiter));
    const NineBitRequest request = built(nine_bit_write_eeprom_request(7, 20, 65535, delimiter));
    CHECK(request.body == bytes(std::string("E20") + delimiter + "65535\r\n"));
    const auto line = command(std::string("E20") + delimiter + "65535");
    CHECK(line.location == 20);
    CHECK(line.value == 65535);
  }
  CHECK(nine_bit_write_eeprom_request(7, 20, 1, ';').error().message ==
        "the delimiter must be a space, ',', ':' or a tab");
}

TEST_CASE("the other commands are one character and CR LF, read EEPROM adds the location (A2)") {
  CHECK(nine_bit_read_temperature_request(5).body == bytes("C\r\n"));
  CHECK(nine_bit_firmware_request(255).body == bytes("F\r\n"));
  CHECK(wire_bytes(nine_bit_firmware_request(255)).front() == 0xFF);
  CHECK(built(nine_bit_read_eeprom_request(3, 4)).body == bytes("34\r\n"));
  CHECK(built(nine_bit_read_eeprom_request(3, 280)).body == bytes("3280\r\n"));
  CHECK(command("34").location == 4);
  CHECK(command("3100").location == 100);
  CHECK(kNineBitAddressBytes == 1);
}

TEST_CASE("the request builders check the location and the value") {
  CHECK(nine_bit_read_eeprom_request(0, 5).error().message ==
        "EEPROM location 5 is odd; locations are even");
  CHECK_FALSE(nine_bit_read_eeprom_request(0, 0).has_value());
  CHECK_FALSE(nine_bit_read_eeprom_request(0, 24).has_value());
  CHECK_FALSE(nine_bit_read_eeprom_request(0, 282).has_value());
  CHECK(nine_bit_read_eeprom_request(0, 100).has_value());
  CHECK(nine_bit_write_eeprom_request(0, 6, 65536).error().message ==
        "EEPROM value 65536 is out of range 0..65535");
  CHECK_FALSE(nine_bit_write_eeprom_request(0, 6, -1).has_value());
}

TEST_CASE("the sensor side rejects commands it cannot read") {
  CHECK(parse_nine_bit_body("").error() == "empty command");
  CHECK(parse_nine_bit_body("B").error() == "unknown command \"B\"");
  CHECK(parse_nine_bit_body("3").error() == "no EEPROM location (0..65535)");
  CHECK(parse_nine_bit_body("E34").error() == "no delimiter after the EEPROM location");
  CHECK(parse_nine_bit_body("E34,").error() == "no value (0..65535)");
  CHECK(parse_nine_bit_body("E34,65536").error() == "no value (0..65535)");
  CHECK(parse_nine_bit_body("A1").error() == "unexpected \"1\" after the command");
  CHECK(parse_nine_bit_body("a").error() == "unknown command \"a\"");
  CHECK(parse_nine_bit_body("A\x01").error() == "unexpected \"\\x01\" after the command");
  CHECK(command("F").command == NineBitCommand::firmware);
  CHECK_FALSE(command("A").location.has_value());
}

TEST_CASE("numbers are read tolerantly and the text is kept") {
  struct Case {
    const char* line;
    std::int32_t value;
  };
  for (const Case& c : {Case{"1001", 1001}, Case{"  0042 ", 42}, Case{"-17", -17},
                        Case{"+5", 5}, Case{"\t-0000300\t", -300}, Case{"0", 0},
                        Case{"65535", 65535}, Case{"-2147483648", -2147483647 - 1}}) {
    CAPTURE(c.line);
    const auto number = parse_nine_bit_number(c.line);
    REQUIRE(number.has_value());
    CHECK(number->value == c.value);
    CHECK(number->text == c.line);
  }
  for (const char* bad : {"", " ", "-", "+-5", "12a", "1 2", "0x10", "2147483648", "A"}) {
    CAPTURE(bad);
    const auto number = parse_nine_bit_number(bad);
    REQUIRE_FALSE(number.has_value());
    CHECK(number.error().kind == ReplyError::Kind::bad_text);
  }
  CHECK(describe(parse_nine_bit_number("12a").error()) ==
        "unreadable reply: expected a decimal number, got \"12a\"");
}

TEST_CASE("the firmware reply is free text, trimmed") {
  CHECK(*parse_nine_bit_firmware(" DYNA 1.07 ") == "DYNA 1.07");
  CHECK_FALSE(parse_nine_bit_firmware("  ").has_value());
  CHECK(nine_bit_reply_line("DYNA") == bytes("DYNA\r\n"));
  CHECK(nine_bit_reply_line("") == bytes("\r\n"));
}

TEST_CASE("the line parser ends lines at CR LF only and drops noise bytes (A5)") {
  NineBitLineParser parser;
  parser.feed(Bytes{0x00, 0xFF, '1', 0x80, '0', '0', '1', '\r', '\n'});
  parser.feed(bytes("\r\n"));           // an empty line: a reset or write acknowledgement
  parser.feed(bytes("12\r34\n56\r\n"));  // a lone CR and a lone LF are noise
  CHECK(lines(parser) == std::vector<std::string>{"1001", "", "123456"});
  CHECK(parser.counters().lines_ok == 3);
  CHECK(parser.counters().bytes_dropped == 5);
}

TEST_CASE("the line parser drops an overlong line up to its CR LF and keeps the next") {
  NineBitLineParser parser;
  parser.feed(Bytes(kMaxLineLength, '7'));
  CHECK(parser.buffered() == kMaxLineLength);
  parser.feed(bytes("8888\r\n-5\r\n"));
  CHECK(lines(parser) == std::vector<std::string>{"-5"});
  CHECK(parser.counters().overlong_lines == 1);
  CHECK(parser.buffered() == 0);
  // Exactly kMaxLineLength characters is still a line.
  parser.feed(Bytes(kMaxLineLength, '1'));
  parser.feed(bytes("\r\n"));
  CHECK(lines(parser) == std::vector<std::string>{std::string(kMaxLineLength, '1')});
}

TEST_CASE("the line parser gives the same lines fed a byte at a time (fixed seed)") {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int round = 0; round < 100; ++round) {
    Bytes stream;
    for (int i = 0; i < 400; ++i) {
      const int b = byte(rng);
      // Frequent CR and LF so that lines of every length end.
      stream.push_back(static_cast<std::uint8_t>(b < 20 ? '\r' : b < 40 ? '\n' : b));
    }
    NineBitLineParser whole;
    whole.feed(stream);
    NineBitLineParser single;
    std::vector<std::string> one_by_one;
    for (std::uint8_t b : stream) {
      single.feed(std::span(&b, 1));
      REQUIRE(single.buffered() <= kMaxLineLength);
      for (auto& line : lines(single)) one_by_one.push_back(std::move(line));
    }
    const auto all = lines(whole);
    CHECK(one_by_one == all);
    for (const auto& line : all) {
      CHECK(line.size() <= kMaxLineLength);
      for (char c : line) CHECK(((c >= 0x20 && c <= 0x7E) || c == '\t'));
    }
  }
}

TEST_CASE("the reply framer completes on the first line and ignores what follows") {
  NineBitReplyFramer framer;
  CHECK_FALSE(framer.feed(bytes("10")));
  CHECK_FALSE(framer.feed(bytes("01\r")));
  CHECK(framer.feed(bytes("\n-3\r\n")));
  CHECK(framer.reply() == "1001");
  CHECK(framer.feed(bytes("more")));
  CHECK(framer.reply() == "1001");
  framer.reset();
  CHECK_FALSE(framer.reply().has_value());
  CHECK(framer.feed(bytes("\r\n")));
  CHECK(framer.reply() == "");
}
