// The pcapng file a capture writes (docs/diagnostics.md, "Capture for Wireshark"): a section
// header, one interface of link type 252 (Wireshark's "upper PDU export"), then one packet per
// frame whose exported PDU names the dissector that reads it (the protocol descriptor's
// wireshark_dissector: one of Wireshark's own, or of packaging/wireshark/tiltgate.lua). Each packet
// has the time of the frame's first byte, its direction in the packet's flags (outbound: the
// gateway's request) and the line's verdict as its comment, so Wireshark opens the file with no
// preference set. Pure: bytes out, nothing written here.
//
// File format: the pcapng draft (IETF opsawg, "PCAP Next Generation Dump File Format"), little
// endian; the exported PDU's tags (big endian) as Wireshark's epan/exported_pdu.h numbers them.
#pragma once

#include <string>
#include <string_view>

#include "driver/captured_frame.h"
#include "driver/family.h"

namespace tiltgate {

// The section header and the interface, once at the start of a file. `application` names the
// writer (shb_userappl), `interface` the bus (if_name).
std::string pcapng_header(std::string_view application, std::string_view interface);

// How a bus's frames are exported: the Wireshark dissector that reads its protocol, and whether
// its devices speak TCP (Wireshark's Modbus/TCP dissector then tells a query from a response by
// the TCP ports, which each packet is given: 502 is the device's).
struct PcapngFormat {
  std::string_view dissector;
  bool over_tcp = false;
};
// From the bus's protocol (ProtocolDescriptor::wireshark_dissector, devices_speak_tcp).
PcapngFormat pcapng_format_of(const ProtocolDescriptor& protocol);

// One frame's packet.
std::string pcapng_packet(const CapturedFrame& frame, const PcapngFormat& format);

}  // namespace tiltgate
