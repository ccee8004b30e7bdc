// A [[bus]] port and what it decides about the bus's other keys. The port is a local tty, a
// serial device server (tcp://, rfc2217://: device_server/port_url.h), or devices that speak
// TCP themselves (ProtocolDescriptor::devices_speak_tcp); each refuses what it cannot carry,
// at the key's line (docs/operations.md, "Serial device servers"). Read by bus_section.cpp.
#pragma once

#include <optional>

#include "config/sections.h"
#include "device_server/port_url.h"

namespace tiltgate::config {

// `port`, parsed only: nothing is resolved or connected. None when missing or in error (the
// error is reported at the key).
std::optional<PortAddress> read_port(TableReader& in, BusConfig& bus);

// Whether the bus's protocol has no serial line at all: its devices speak TCP themselves.
bool devices_speak_tcp(ProtocolEntry protocol);

// On such a bus the serial line's keys (baud, parity, stop_bits, gap_us, rs485, echo) mean
// nothing: each one given is refused. They are read here instead of by the serial readers.
void refuse_serial_line_keys(TableReader& in, ProtocolEntry protocol);

// The port against the protocol and the keys read so far: a protocol whose devices speak TCP
// needs tcp://; a 9-bit framing needs a local tty; rs485 = true needs a local tty.
void check_port_fits(TableReader& in, const BusConfig& bus, const PortAddress& port,
                     ProtocolEntry protocol);

}  // namespace tiltgate::config
