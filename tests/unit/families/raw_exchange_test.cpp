// `tiltgate raw`: each family's hook builds the exact request for a function number and data,
// and decodes the reply its framer accepts (ACK, NAK or exception with its meaning, values).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "driver/family.h"
#include "driver/family_commands.h"
#include "driver/hex.h"
#include "modbus_rtu/codec.h"
#include "rieker/codec.h"
#include "spectron/ascii_codec.h"

using namespace tiltgate;

namespace {

std::unique_ptr<RawExchange> exchange(std::string_view protocol, std::uint32_t address,
                                      std::int64_t function, std::vector<std::uint8_t> data = {},
                                      std::uint32_t master = 0) {
  const ProtocolEntry entry = find_protocol(registered_families(), protocol);
  REQUIRE(entry.family);
  const FamilyCommands* commands = find_commands(registered_family_commands(), entry.family);
  REQUIRE(commands);
  const bool has_raw = commands->raw.make != nullptr;
  REQUIRE(has_raw);
  auto made = commands->raw.make(RawSetup{protocol, address, master, function, std::move(data)});
  REQUIRE_MESSAGE(made, (made ? "" : made.error()));
  return std::move(*made);
}

std::string usage_error(std::string_view protocol, std::int64_t function,
                        std::vector<std::uint8_t> data = {}) {
  const ProtocolEntry entry = find_protocol(registered_families(), protocol);
  const FamilyCommands* commands = find_commands(registered_family_commands(), entry.family);
  REQUIRE(commands);
  auto made = commands->raw.make(RawSetup{protocol, 1, 0, function, std::move(data)});
  REQUIRE_FALSE(made);
  return made.error();
}

// Feeds `reply` to the request's framer as the Line would, and decodes it.
RawReply answer(RawExchange& raw, const LineRequest& request, const std::vector<std::uint8_t>& reply) {
  request.framer->reset();
  REQUIRE(request.framer->feed(reply));
  CHECK(request.framer->report().reply == reply);
  return raw.decode();
}

std::vector<std::uint8_t> bytes(std::string_view text) { return {text.begin(), text.end()}; }

}  // namespace

TEST_CASE("raw on a Rieker bus: FUNCT and DATA framed with DEST, SRC and CRC, with NAK and serial decoded") {
  auto raw = exchange("rieker", 223, 37, {}, 5);
  const LineRequest request = raw->request();
  CHECK(request.bytes == rieker::encode(rieker::Frame{223, 5, 37, {}}));
  CHECK(request.address_bytes == 0);

  const RawReply serial = answer(*raw, request, rieker::encode(rieker::make_serial_reply(5, 223, "9600223")));
  CHECK_FALSE(serial.refused);
  CHECK(serial.text.find("function 37 (get serial number)") != std::string::npos);
  CHECK(serial.text.find("serial:   9600223") != std::string::npos);

  const RawReply nak = answer(*raw, request, rieker::encode(rieker::make_nak(5, 223, rieker::NakCode::wrong_lock_level)));
  CHECK(nak.refused);
  CHECK(nak.text == "reply:    NAK 4 (wrong lock level)");

  const RawReply ack = answer(*raw, request, rieker::encode(rieker::make_ack(5, 223)));
  CHECK_FALSE(ack.refused);
  CHECK(ack.text == "reply:    ACK");
  CHECK(usage_error("rieker", 70000).find("not a command code") != std::string::npos);
}

TEST_CASE("raw on a Modbus RTU bus: the PDU framed with slave and CRC, and an exception is a refusal") {
  auto raw = exchange("modbus-rtu", 1, 3, {0x00, 0x00, 0x00, 0x02});
  const LineRequest request = raw->request();
  CHECK(hex_bytes(request.bytes) == "01 03 00 00 00 02 C4 0B");  // Serial Line spec's example CRC
  const RawReply refused = answer(*raw, request, modbus_rtu::exception_frame(1, 3, modbus_rtu::ExceptionCode::illegal_data_address));
  CHECK(refused.refused);
  CHECK(refused.text == "reply:    exception 0x02 (illegal data address)");

  std::vector<std::uint8_t> registers{0x01, 0x03, 0x04, 0x00, 0x04, 0xDA, 0x15};
  const std::uint16_t crc = 0x5D21;  // as the simulator sent it: 21 5D
  registers.push_back(std::uint8_t(crc & 0xFF));
  registers.push_back(std::uint8_t(crc >> 8));
  const RawReply read = answer(*raw, request, registers);
  CHECK_FALSE(read.refused);
  CHECK(read.text == "reply:    function 0x03, PDU 03 04 00 04 DA 15\nregisters: 4 55829");
  CHECK(usage_error("modbus-rtu", 0).find("not a Modbus function code") != std::string::npos);
  CHECK(usage_error("modbus-rtu", 128).find("not a Modbus function code") != std::string::npos);
}

TEST_CASE("raw on a modbus-tcp bus: the PDU in an MBAP frame, and only its transaction's reply") {
  auto raw = exchange("modbus-tcp", 255, 3, {0x00, 0x00, 0x00, 0x02});
  const LineRequest request = raw->request();
  REQUIRE(request.bytes.size() == 12);
  // Transaction id (the gateway's own), protocol 0, length 6, unit 255, then the PDU.
  CHECK(hex_bytes({request.bytes.data() + 2, 10}) == "00 00 00 06 FF 03 00 00 00 02");
  std::vector<std::uint8_t> reply{request.bytes[0], request.bytes[1], 0x00, 0x00, 0x00, 0x07,
                                  0xFF, 0x03, 0x04, 0x00, 0x04, 0xDA, 0x15};
  std::vector<std::uint8_t> other = reply;
  other[1] ^= 0x01;  // another transaction's reply: not this one's
  request.framer->reset();
  CHECK_FALSE(request.framer->feed(other));
  CHECK(request.framer->feed(reply));
  const RawReply read = raw->decode();
  CHECK_FALSE(read.refused);
  CHECK(read.text == "reply:    function 0x03, PDU 03 04 00 04 DA 15\nregisters: 4 55829");
}

TEST_CASE("raw on a Dyna bus: Modbus-ASCII command and data with LRC, and on 9-bit the command character after the address byte") {
  auto ascii = exchange("spectron-modbus", 1, 0x69, {0x00, 0x10});
  const LineRequest request = ascii->request();
  CHECK(request.bytes == bytes(":01690010" "6F" "\r\n"));  // LRC as the module's simulator checks it
  const RawReply word = answer(*ascii, request,
                               spectron::encode(spectron::make_ascii_word_reply(1, spectron::AsciiCommand::read_eeprom, 0xFFFE)));
  CHECK_FALSE(word.refused);
  CHECK(word.text.find("command 0x69 (read EEPROM), 2 data byte(s): FF FE") != std::string::npos);
  CHECK(word.text.find("word:     65534 (signed -2)") != std::string::npos);

  auto nine_bit = exchange("spectron-9bit", 1, 'A');
  const LineRequest nine = nine_bit->request();
  CHECK(nine.bytes == std::vector<std::uint8_t>{0x01, 'A', '\r', '\n'});
  CHECK(nine.address_bytes == 1);
  const RawReply text = answer(*nine_bit, nine, bytes("1011\r\n"));
  CHECK(text.text == "reply:    \"1011\"");
  CHECK(usage_error("spectron-9bit", 256).find("not a command code") != std::string::npos);
}

TEST_CASE("hex bytes as typed: spaces, commas, 0x and runs of digits, with odd or foreign digits refused") {
  CHECK(parse_hex_bytes("01 03 0a FF") == std::vector<std::uint8_t>{0x01, 0x03, 0x0A, 0xFF});
  CHECK(parse_hex_bytes("01030A") == std::vector<std::uint8_t>{0x01, 0x03, 0x0A});
  CHECK(parse_hex_bytes("0x01,0x10") == std::vector<std::uint8_t>{0x01, 0x10});
  CHECK(parse_hex_bytes("") == std::vector<std::uint8_t>{});
  CHECK_FALSE(parse_hex_bytes("1 2"));
  CHECK_FALSE(parse_hex_bytes("0g"));
  CHECK_FALSE(parse_hex_bytes("010"));
}
