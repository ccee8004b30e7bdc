#include "config/bus_port.h"

#include <fmt/format.h>

#include <string_view>
#include <vector>

#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::Presence;

namespace {

// The keys of a serial line: its rate and framing, its quiet time, and the adapter's own ways.
constexpr std::string_view kSerialLineKeys[] = {"baud",   "parity", "stop_bits",
                                                "gap_us", "rs485",  "echo"};

// The family's protocols a 9-bit bus could move to over a network: those framed in plain
// characters on a serial line (its Modbus-ASCII protocol, say).
std::vector<std::string> network_alternatives(const FamilyDescriptor& family) {
  std::vector<std::string> names;
  for (const ProtocolDescriptor& other : family.protocols)
    if (other.framing != Framing::nine_bit && !other.devices_speak_tcp)
      names.push_back(fmt::format("protocol = \"{}\" ({})", other.name, other.title));
  return names;
}

// Why the ninth bit cannot cross a device server: it is the parity bit, switched per byte
// (docs/operations.md, "9-bit framing").
void refuse_nine_bit(TableReader& in, const BusConfig& bus, ProtocolEntry protocol) {
  const std::vector<std::string> alternatives = network_alternatives(*protocol.family);
  const std::string instead =
      alternatives.empty()
          ? std::string("use a local serial port")
          : fmt::format("use {} with the same sensors, or a local serial port",
                        fmt::join(alternatives, " or "));
  in.error("port",
           fmt::format("\"{}\": {} framing needs a local serial port: its ninth bit is the parity "
                       "bit switched per byte (mark for the address byte, space for the data); "
                       "raw TCP cannot switch the far port's parity at all, and RFC 2217's "
                       "SET-PARITY is not applied in step with the bytes around it "
                       "(docs/operations.md, \"Serial device servers\"); {}",
                       bus.port, protocol.protocol->title, instead));
}

}  // namespace

std::optional<PortAddress> read_port(TableReader& in, BusConfig& bus) {
  auto text = in.string("port", Presence::required);
  if (!text) return std::nullopt;
  bus.port = *text;
  auto port = parse_port(*text);
  if (!port) {
    in.error("port", port.error());
    return std::nullopt;
  }
  return *port;
}

bool devices_speak_tcp(ProtocolEntry protocol) {
  return protocol.protocol != nullptr && protocol.protocol->devices_speak_tcp;
}

void refuse_serial_line_keys(TableReader& in, ProtocolEntry protocol) {
  for (std::string_view key : kSerialLineKeys) {
    // Asked for, so that it is refused here and not as an unknown key.
    if (in.node(key) == nullptr) continue;
    in.error(key, fmt::format("a {} bus has no serial line: the devices speak {}",
                              protocol.protocol->name, protocol.protocol->title));
  }
}

void check_port_fits(TableReader& in, const BusConfig& bus, const PortAddress& port,
                     ProtocolEntry protocol) {
  if (protocol.protocol == nullptr) return;
  const ProtocolDescriptor& descriptor = *protocol.protocol;
  if (descriptor.devices_speak_tcp) {
    if (port.scheme == PortScheme::tty)
      in.error("port", fmt::format("\"{}\" is a tty, but {} devices speak {} themselves: "
                                   "expected port = \"tcp://HOST:PORT\" (the device's address)",
                                   bus.port, descriptor.name, descriptor.title));
    else if (port.scheme == PortScheme::rfc2217)
      in.error("port", fmt::format("rfc2217:// sets a serial port's rate and framing, but {} "
                                   "devices speak {} themselves: expected port = "
                                   "\"tcp://{}\"",
                                   descriptor.name, descriptor.title, port.endpoint()));
    return;
  }
  if (!port.over_network()) return;
  if (descriptor.framing == Framing::nine_bit) refuse_nine_bit(in, bus, protocol);
  if (bus.rs485_kernel && in.located().valid("rs485"))
    in.error("rs485", fmt::format("true on a device server port (\"{}\"): the server drives its "
                                  "own RS485 transmitter; leave rs485 out or false",
                                  bus.port));
}

}  // namespace tiltgate::config
