// What the control socket reads from a command's Dyna request, on either protocol, for the
// audit trail (spectron/request_reader.h), from the application note's frames.
#include <doctest/doctest.h>

#include "spectron/ascii_codec.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/request_reader.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::spectron;

namespace {

std::vector<std::uint8_t> nine_bit(std::uint8_t address, std::string_view line) {
  std::vector<std::uint8_t> bytes{address};
  bytes.insert(bytes.end(), line.begin(), line.end());
  return bytes;
}

std::vector<std::uint8_t> bytes_of(std::string_view text) { return {text.begin(), text.end()}; }

}  // namespace

TEST_CASE("a 9-bit write EEPROM or reset may change the module, and the reads do not") {
  const auto write = read_nine_bit_request(nine_bit(7, "E100 355\r\n"));
  REQUIRE(write);
  CHECK(write->address == 7);
  CHECK(write->may_change);
  CHECK(write->function == "command E (write EEPROM)");
  CHECK(write->data == "100 355");
  CHECK(read_nine_bit_request(nine_bit(7, "0\r\n"))->may_change);
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "A\r\n"))->may_change);
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "C\r\n"))->may_change);
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "F\r\n"))->may_change);
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "3100\r\n"))->may_change);
  CHECK(read_nine_bit_request(wire_bytes(nine_bit_read_sensor_request(9)))->address == 9);
}

TEST_CASE("a 9-bit request without CR LF or with an unknown command is not read") {
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "E100 355")));
  CHECK_FALSE(read_nine_bit_request(nine_bit(7, "Z\r\n")));
  CHECK_FALSE(read_nine_bit_request({}));
}

TEST_CASE("a Modbus-ASCII write EEPROM may change the module, and a read sensor does not") {
  const auto write = read_ascii_request(test::bytes(":0268006401639C\r\n"));
  REQUIRE(write);
  CHECK(write->address == 2);
  CHECK(write->may_change);
  CHECK(write->function == "command 68 (write EEPROM)");
  CHECK(write->data == "00640163");
  CHECK_FALSE(read_ascii_request(test::bytes(":016633\r\n"))->may_change);
  CHECK_FALSE(read_ascii_request(test::bytes(":146900026A\r\n"))->may_change);
  CHECK_FALSE(read_ascii_request(test::bytes(":0268006401639D\r\n")));  // the LRC
}

TEST_CASE("the Dyna has no refusal reply") {
  CHECK_FALSE(read_refusal(test::bytes(":026830\r\n")));
}

TEST_CASE("a Dyna reply is read as the answer to its request, on either protocol") {
  CHECK(read_nine_bit_reply(nine_bit(5, "A\r\n"), bytes_of("1001\r\n")) == "counts 1001");
  CHECK(read_nine_bit_reply(nine_bit(5, "C\r\n"), bytes_of("-12\r\n")) == "temperature counts -12");
  CHECK(read_nine_bit_reply(nine_bit(5, "E6,100\r\n"), bytes_of("1\r\n")) == "ack");
  CHECK_FALSE(read_nine_bit_reply(nine_bit(5, "A\r\n"), bytes_of("12x4\r\n")));  // no number
  CHECK_FALSE(read_nine_bit_reply(nine_bit(5, "A\r\n"), bytes_of("1001")));      // no CR LF

  const auto read_sensor = ascii_read_sensor_request(7);
  REQUIRE(read_sensor);
  const std::vector<std::uint8_t> reply =
      encode(make_ascii_word_reply(7, AsciiCommand::read_sensor, std::uint16_t(1250)));
  CHECK(read_ascii_reply(encode(*read_sensor), reply) == "counts 1250");
  // From another module: not its answer.
  CHECK_FALSE(read_ascii_reply(
      encode(*read_sensor), encode(make_ascii_word_reply(8, AsciiCommand::read_sensor, 1250))));
  const auto reset = ascii_reset_request(7);
  REQUIRE(reset);
  CHECK(read_ascii_reply(encode(*reset), encode(make_ascii_ack(7, AsciiCommand::reset))) == "ack");
}
