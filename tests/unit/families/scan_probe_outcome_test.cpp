// What each family's scan probe makes of the bytes that came back (driver/scan.h): a reply
// from the address probed, bytes that failed their checksum (two sensors answering at once),
// or nothing. The framers are fed as the Line would feed them.
#include <doctest/doctest.h>

#include "modbus_rtu/scan_probe.h"
#include "rieker/scan_probe.h"
#include "spectron/ascii_codec.h"
#include "spectron/scan_probe.h"

using namespace tiltgate;

namespace {

std::vector<std::uint8_t> text_bytes(std::string_view text) {
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

rieker::RiekerReplyFramer rieker_check_address(std::uint16_t address) {
  auto request = rieker::check_address_request(rieker::Route{address, 0});
  REQUIRE(request.has_value());
  rieker::RiekerReplyFramer framer(*request);
  framer.reset();
  return framer;
}

spectron::DynaTransaction dyna_read_sensor(spectron::Protocol protocol, int address) {
  auto transaction = spectron::DynaTransaction::make(
      protocol, address, spectron::DynaRequest{spectron::DynaRequest::Kind::read_sensor});
  REQUIRE(transaction.has_value());
  transaction->line_request().framer->reset();
  return std::move(*transaction);
}

// Feeds `bytes`; whether the framer then holds a whole reply.
bool feed(ReplyFramer& framer, const std::vector<std::uint8_t>& bytes) {
  return framer.feed(bytes);
}

}  // namespace

TEST_CASE("Rieker: the ACK to Check Address 223 is a sensor at 223") {
  auto framer = rieker_check_address(223);
  // docs/protocols.md, "Rieker verified frames": 0000 00DF 0000 00 D43B, the ACK from 223.
  REQUIRE(feed(framer, {0x00, 0x00, 0x00, 0xDF, 0x00, 0x00, 0x00, 0xD4, 0x3B}));
  const ProbeResult result = rieker::probe_outcome(framer);
  CHECK(result.outcome == ProbeOutcome::answered);
  CHECK(result.address == 223u);
  CHECK(result.detail.empty());
}

TEST_CASE("Rieker: the ACK with a broken CRC is a probable collision, not silence") {
  auto framer = rieker_check_address(223);
  CHECK_FALSE(feed(framer, {0x00, 0x00, 0x00, 0xDF, 0x00, 0x00, 0x00, 0xD4, 0xC4}));
  const ProbeResult result = rieker::probe_outcome(framer);
  CHECK(result.outcome == ProbeOutcome::garbled);
  CHECK(result.detail == "bad CRC");
  CHECK_FALSE(result.address.has_value());
}

TEST_CASE("Rieker: nothing back is silence, but a NAK still shows a sensor there") {
  auto silent = rieker_check_address(5);
  CHECK(rieker::probe_outcome(silent).outcome == ProbeOutcome::silent);

  auto refused = rieker_check_address(5);
  REQUIRE(feed(refused, rieker::encode(rieker::make_nak(0, 5, rieker::NakCode::busy))));
  const ProbeResult result = rieker::probe_outcome(refused);
  CHECK(result.outcome == ProbeOutcome::answered);
  CHECK(result.address == 5u);
  CHECK(result.detail.find("NAK 5") == 0);
}

TEST_CASE("Rieker: the broadcast Get Address reply gives the sensor's own address") {
  auto request = rieker::get_address_request(rieker::Route{rieker::kBroadcastAddress, 0});
  REQUIRE(request.has_value());
  rieker::RiekerReplyFramer framer(*request);
  framer.reset();
  // docs/protocols.md, "Rieker verified frames": 0000 00DF 0003 02 00DF 73F3, "address 223".
  REQUIRE(feed(framer, {0x00, 0x00, 0x00, 0xDF, 0x00, 0x03, 0x02, 0x00, 0xDF, 0x73, 0xF3}));
  const ProbeResult result = rieker::probe_outcome(framer);
  CHECK(result.outcome == ProbeOutcome::answered);
  CHECK(result.address == 223u);
}

TEST_CASE("Dyna 9-bit: a number is a module, a line that is no number is a probable collision") {
  auto answered = dyna_read_sensor(spectron::Protocol::nine_bit, 3);
  REQUIRE(feed(*answered.line_request().framer, text_bytes("1234\r\n")));
  const ProbeResult result = spectron::probe_outcome(answered, 3, true);
  CHECK(result.outcome == ProbeOutcome::answered);
  CHECK(result.address == 3u);

  auto garbled = dyna_read_sensor(spectron::Protocol::nine_bit, 3);
  REQUIRE(feed(*garbled.line_request().framer, text_bytes("1#34\r\n")));
  CHECK(spectron::probe_outcome(garbled, 3, true).outcome == ProbeOutcome::garbled);

  auto silent = dyna_read_sensor(spectron::Protocol::nine_bit, 3);
  CHECK(spectron::probe_outcome(silent, 3, false).outcome == ProbeOutcome::silent);
}

TEST_CASE("Dyna Modbus-ASCII: the module's reply is a module, a bad LRC is a probable collision") {
  const auto reply = spectron::encode_text(
      spectron::make_ascii_word_reply(7, spectron::AsciiCommand::read_sensor, 1234));
  auto answered = dyna_read_sensor(spectron::Protocol::modbus_ascii, 7);
  REQUIRE(feed(*answered.line_request().framer, text_bytes(reply)));
  CHECK(spectron::probe_outcome(answered, 7, true).outcome == ProbeOutcome::answered);

  std::string broken = reply;
  const std::size_t lrc_digit = broken.size() - 3;  // the LRC's last digit, before CR LF
  broken[lrc_digit] = broken[lrc_digit] == '0' ? '1' : '0';
  auto garbled = dyna_read_sensor(spectron::Protocol::modbus_ascii, 7);
  CHECK_FALSE(feed(*garbled.line_request().framer, text_bytes(broken)));
  const ProbeResult result = spectron::probe_outcome(garbled, 7, false);
  CHECK(result.outcome == ProbeOutcome::garbled);
  CHECK(result.detail == "bad LRC");
}

TEST_CASE("Modbus RTU: FC 17 without a profile, the profile's first block with one") {
  auto report = modbus_rtu::probe_request(9, std::nullopt);
  REQUIRE(report.has_value());
  CHECK(report->frame.size() == 4);  // address, 0x11, CRC
  CHECK(report->frame[1] == modbus_rtu::kReportServerId);

  auto block = modbus_rtu::probe_request(
      9, modbus_rtu::ReadBlock{modbus_rtu::RegisterBank::holding, 100, 4});
  REQUIRE(block.has_value());
  CHECK(block->frame ==
        modbus_rtu::read_request(9, modbus_rtu::RegisterBank::holding, 100, 4)->frame);
}

TEST_CASE("Modbus RTU: an exception reply is a device there, a bad CRC a probable collision") {
  auto request = modbus_rtu::probe_request(9, std::nullopt);
  REQUIRE(request.has_value());
  const auto exception = modbus_rtu::exception_frame(9, modbus_rtu::kReportServerId,
                                                     modbus_rtu::ExceptionCode::illegal_function);

  modbus_rtu::RtuReplyFramer answered(*request);
  answered.reset();
  REQUIRE(feed(answered, exception));
  const ProbeResult result = modbus_rtu::probe_outcome(answered, 9);
  CHECK(result.outcome == ProbeOutcome::answered);
  CHECK(result.address == 9u);
  CHECK(result.detail.find("exception 1") == 0);

  auto broken = exception;
  broken.back() ^= 0xFF;
  modbus_rtu::RtuReplyFramer garbled(*request);
  garbled.reset();
  CHECK_FALSE(feed(garbled, broken));
  CHECK(modbus_rtu::probe_outcome(garbled, 9).outcome == ProbeOutcome::garbled);

  modbus_rtu::RtuReplyFramer silent(*request);
  silent.reset();
  CHECK(modbus_rtu::probe_outcome(silent, 9).outcome == ProbeOutcome::silent);
}
