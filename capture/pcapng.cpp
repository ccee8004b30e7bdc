#include "capture/pcapng.h"

#include <cstdint>

namespace tiltgate {

namespace {

constexpr std::uint32_t kSectionHeader = 0x0A0D0D0A;
constexpr std::uint32_t kInterfaceDescription = 1;
constexpr std::uint32_t kEnhancedPacket = 6;
constexpr std::uint32_t kByteOrderMagic = 0x1A2B3C4D;
constexpr std::uint16_t kLinkTypeUpperPdu = 252;  // LINKTYPE_WIRESHARK_UPPER_PDU

// Options (pcapng): opt_endofopt, opt_comment, shb_userappl, if_name, epb_flags.
constexpr std::uint16_t kEndOfOptions = 0;
constexpr std::uint16_t kComment = 1;
constexpr std::uint16_t kInterfaceName = 2;
constexpr std::uint16_t kUserApplication = 4;
constexpr std::uint16_t kPacketFlags = 2;
constexpr std::uint32_t kInbound = 1;   // epb_flags bits 0-1: the direction
constexpr std::uint32_t kOutbound = 2;

// Exported PDU tags (epan/exported_pdu.h): the dissector's name, and for a protocol over TCP
// the TCP ports (PcapngFormat::over_tcp).
constexpr std::uint16_t kTagEnd = 0;
constexpr std::uint16_t kTagProtocolName = 12;
constexpr std::uint16_t kTagPortType = 24;
constexpr std::uint16_t kTagSourcePort = 25;
constexpr std::uint16_t kTagDestinationPort = 26;
constexpr std::uint32_t kPortTypeTcp = 2;
constexpr std::uint32_t kModbusTcpPort = 502;
// A port for the gateway's side of a Modbus/TCP exchange, any but 502.
constexpr std::uint32_t kGatewayPort = 50200;

void put_le16(std::string& out, std::uint16_t v) {
  out.push_back(char(v & 0xFF));
  out.push_back(char(v >> 8));
}
void put_le32(std::string& out, std::uint32_t v) {
  put_le16(out, std::uint16_t(v & 0xFFFF));
  put_le16(out, std::uint16_t(v >> 16));
}
void put_be16(std::string& out, std::uint16_t v) {
  out.push_back(char(v >> 8));
  out.push_back(char(v & 0xFF));
}
void put_be32(std::string& out, std::uint32_t v) {
  put_be16(out, std::uint16_t(v >> 16));
  put_be16(out, std::uint16_t(v & 0xFFFF));
}
void pad_to_32_bits(std::string& out) {
  while (out.size() % 4 != 0) out.push_back('\0');
}

void put_option(std::string& out, std::uint16_t code, std::string_view value) {
  put_le16(out, code);
  put_le16(out, std::uint16_t(value.size()));
  out.append(value);
  pad_to_32_bits(out);
}

// A block: type, total length, body (padded), total length again.
std::string block(std::uint32_t type, std::string body) {
  pad_to_32_bits(body);
  std::string out;
  const auto total = std::uint32_t(12 + body.size());
  put_le32(out, type);
  put_le32(out, total);
  out += body;
  put_le32(out, total);
  return out;
}

// An exported PDU tag; a string's length is given padded, as Wireshark writes it.
void put_tag(std::string& out, std::uint16_t tag, std::string_view value) {
  std::string padded(value);
  pad_to_32_bits(padded);
  put_be16(out, tag);
  put_be16(out, std::uint16_t(padded.size()));
  out += padded;
}
void put_tag32(std::string& out, std::uint16_t tag, std::uint32_t value) {
  put_be16(out, tag);
  put_be16(out, 4);
  put_be32(out, value);
}

}  // namespace

std::string pcapng_header(std::string_view application, std::string_view interface) {
  std::string section;
  put_le32(section, kByteOrderMagic);
  put_le16(section, 1);  // version 1.0
  put_le16(section, 0);
  put_le32(section, 0xFFFFFFFF);  // section length: not given (-1), the file may be a stream
  put_le32(section, 0xFFFFFFFF);
  put_option(section, kUserApplication, application);
  put_option(section, kEndOfOptions, {});

  std::string interface_block;
  put_le16(interface_block, kLinkTypeUpperPdu);
  put_le16(interface_block, 0);  // reserved
  put_le32(interface_block, 0);  // snap length: none
  put_option(interface_block, kInterfaceName, interface);
  put_option(interface_block, kEndOfOptions, {});  // time stamps in microseconds (the default)
  return block(kSectionHeader, std::move(section)) +
         block(kInterfaceDescription, std::move(interface_block));
}

PcapngFormat pcapng_format_of(const ProtocolDescriptor& protocol) {
  return {protocol.wireshark_dissector, protocol.devices_speak_tcp};
}

std::string pcapng_packet(const CapturedFrame& frame, const PcapngFormat& format) {
  const bool outbound = frame.direction == FrameDirection::to_devices;
  std::string pdu;
  put_tag(pdu, kTagProtocolName, format.dissector);
  if (format.over_tcp) {
    put_tag32(pdu, kTagPortType, kPortTypeTcp);
    put_tag32(pdu, kTagSourcePort, outbound ? kGatewayPort : kModbusTcpPort);
    put_tag32(pdu, kTagDestinationPort, outbound ? kModbusTcpPort : kGatewayPort);
  }
  put_be16(pdu, kTagEnd);
  put_be16(pdu, 0);
  pdu.append(reinterpret_cast<const char*>(frame.bytes.data()), frame.bytes.size());

  const auto micros = std::uint64_t(std::chrono::duration_cast<std::chrono::microseconds>(
                                        frame.time.time_since_epoch())
                                        .count());
  std::string body;
  put_le32(body, 0);  // interface 0
  put_le32(body, std::uint32_t(micros >> 32));
  put_le32(body, std::uint32_t(micros & 0xFFFFFFFF));
  put_le32(body, std::uint32_t(pdu.size()));  // captured
  put_le32(body, std::uint32_t(pdu.size()));  // on the wire
  body += pdu;
  pad_to_32_bits(body);
  std::string flags;
  put_le32(flags, outbound ? kOutbound : kInbound);
  put_option(body, kPacketFlags, flags);
  std::string comment = frame.verdict;
  if (frame.address_bytes > 0)
    comment += "; 9th bit set on the first " + std::to_string(frame.address_bytes) + " byte(s)";
  if (!comment.empty()) put_option(body, kComment, comment);
  put_option(body, kEndOfOptions, {});
  return block(kEnhancedPacket, std::move(body));
}

}  // namespace tiltgate
