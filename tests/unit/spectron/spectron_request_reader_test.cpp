// What the control socket reads from a command's Dyna request, on either protocol, for the
// audit trail (spectron/request_reader.h), from the application note's frames.
#include <doctest/doctest.h>

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
