// The pcapng a capture writes, read back field by field as the format draft and Wireshark's
// exported PDU lay them out: the section and interface (link type 252), and per frame its
// time, the dissector's name (padded, its padded length given), its direction and verdict.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "capture/pcapng.h"

using namespace tiltgate;

namespace {

std::uint32_t le32_at(const std::string& s, std::size_t at) {
  return std::uint32_t(std::uint8_t(s[at])) | std::uint32_t(std::uint8_t(s[at + 1])) << 8 |
         std::uint32_t(std::uint8_t(s[at + 2])) << 16 | std::uint32_t(std::uint8_t(s[at + 3])) << 24;
}
std::uint16_t le16_at(const std::string& s, std::size_t at) {
  return std::uint16_t(std::uint8_t(s[at]) | std::uint8_t(s[at + 1]) << 8);
}
std::uint16_t be16_at(const std::string& s, std::size_t at) {
  return std::uint16_t(std::uint8_t(s[at]) << 8 | std::uint8_t(s[at + 1]));
}

// Each block's length is given at both ends and is a multiple of 4.
void check_blocks(const std::string& bytes) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    const std::uint32_t length = le32_at(bytes, at + 4);
    REQUIRE(length % 4 == 0);
    REQUIRE(at + length <= bytes.size());
    CHECK(le32_at(bytes, at + length - 4) == length);
    at += length;
  }
  CHECK(at == bytes.size());
}

}  // namespace

TEST_CASE("a pcapng starts with a section header and one upper-PDU interface") {
  const std::string header = pcapng_header("tiltgate 0.1.0", "line1");
  check_blocks(header);
  CHECK(le32_at(header, 0) == 0x0A0D0D0A);
  CHECK(le32_at(header, 8) == 0x1A2B3C4D);  // byte-order magic: little endian
  CHECK(header.find("tiltgate 0.1.0") != std::string::npos);
  const std::size_t interface = le32_at(header, 4);
  CHECK(le32_at(header, interface) == 1);
  CHECK(le16_at(header, interface + 8) == 252);  // LINKTYPE_WIRESHARK_UPPER_PDU
  CHECK(header.find("line1", interface) != std::string::npos);
}

TEST_CASE("a frame's packet holds its time, the dissector, the bytes, its direction and verdict") {
  CapturedFrame frame;
  frame.time = std::chrono::system_clock::time_point(std::chrono::microseconds(0x123456789AB));
  frame.direction = FrameDirection::to_devices;
  frame.bytes = {0x01, 0x03, 0x00, 0x00, 0x00, 0x02, 0xC4, 0x0B};
  frame.verdict = "request";
  const std::string packet = pcapng_packet(frame, {"mbrtu"});
  check_blocks(packet);
  CHECK(le32_at(packet, 0) == 6);                // enhanced packet block
  CHECK(le32_at(packet, 8) == 0);                // interface 0
  CHECK(le32_at(packet, 12) == 0x123);           // time stamp, high 32 bits (microseconds)
  CHECK(le32_at(packet, 16) == 0x456789AB);      // low 32 bits
  const std::uint32_t captured = le32_at(packet, 20);
  CHECK(le32_at(packet, 24) == captured);
  // The exported PDU: tag 12 "mbrtu" padded to 8 with its padded length, the end tag, the frame.
  const std::size_t pdu = 28;
  CHECK(be16_at(packet, pdu) == 12);
  CHECK(be16_at(packet, pdu + 2) == 8);
  CHECK(packet.substr(pdu + 4, 8) == std::string("mbrtu\0\0\0", 8));
  CHECK(be16_at(packet, pdu + 12) == 0);
  CHECK(be16_at(packet, pdu + 14) == 0);
  CHECK(captured == 16 + frame.bytes.size());
  CHECK(packet.substr(pdu + 16, 8) == std::string("\x01\x03\x00\x00\x00\x02\xC4\x0B", 8));
  // Options after the padded data: the flags (outbound) and the verdict as the comment.
  std::size_t option = pdu + ((captured + 3) / 4) * 4;
  CHECK(le16_at(packet, option) == 2);
  CHECK(le16_at(packet, option + 2) == 4);
  CHECK(le32_at(packet, option + 4) == 2);  // outbound
  option += 8;
  CHECK(le16_at(packet, option) == 1);
  CHECK(le16_at(packet, option + 2) == 7);
  CHECK(packet.substr(option + 4, 7) == "request");

  frame.direction = FrameDirection::from_devices;
  const std::string reply = pcapng_packet(frame, {"mbrtu"});
  CHECK(le32_at(reply, pdu + ((captured + 3) / 4) * 4 + 4) == 1);  // inbound
}

TEST_CASE("a Modbus/TCP frame carries the TCP ports its dissector tells a query by") {
  CapturedFrame frame;
  frame.bytes = {0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x00, 0x00, 0x01};
  const std::string packet = pcapng_packet(frame, {"mbtcp", true});
  const std::size_t pdu = 28;
  CHECK(be16_at(packet, pdu) == 12);
  std::size_t tag = pdu + 4 + be16_at(packet, pdu + 2);
  CHECK(be16_at(packet, tag) == 24);       // port type: TCP
  CHECK(be16_at(packet, tag + 8) == 25);   // source port
  CHECK(be16_at(packet, tag + 16) == 26);  // destination port
  CHECK(be16_at(packet, tag + 22) == 502);  // a request goes to the server's port
}

TEST_CASE("a 9-bit frame's comment says which bytes had the 9th bit set") {
  CapturedFrame frame;
  frame.bytes = {0x05, 'A', '\r', '\n'};
  frame.address_bytes = 1;
  frame.verdict = "request";
  const std::string packet = pcapng_packet(frame, {"tiltgate_dyna9"});
  CHECK(packet.find("request; 9th bit set on the first 1 byte(s)") != std::string::npos);
}
