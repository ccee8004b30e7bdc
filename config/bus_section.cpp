// Reading one [[bus]] table: its keys and the checks that depend only on it and on its
// protocol's descriptor (bauds, framing, gap, master address, pass-through; what its port can
// carry: config/bus_port.h). Checks across tables are in config/cross_checks.h and
// config/pass_through_checks.h.
#include <fmt/format.h>

#include <string_view>
#include <vector>

#include "config/bus_port.h"
#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::kAnyInteger;
using toml_input::kAnyIntegerMax;
using toml_input::check_name;
using toml_input::ErrorList;
using toml_input::Located;
using toml_input::TableReader;
using toml_input::Presence;

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

std::vector<std::string_view> protocol_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols) names.push_back(protocol.name);
  return names;
}

// The protocols whose master has an address of its own, and the first one's range (for a bus
// whose protocol is in error).
std::vector<std::string_view> protocols_with_master_address(FamilyList families,
                                                            AddressRange* first_range) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families) {
    for (const ProtocolDescriptor& protocol : family->protocols) {
      if (!protocol.master_addresses) continue;
      if (names.empty()) *first_range = *protocol.master_addresses;
      names.push_back(protocol.name);
    }
  }
  return names;
}

void read_baud(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol) {
  const auto baud = in.integer("baud", kAnyInteger, kAnyIntegerMax);
  if (protocol == nullptr) return;
  const std::span<const std::int64_t> rates = protocol->bauds;
  const std::string expected = fmt::format("expected one of {}", fmt::join(rates, ", "));
  if (!baud) {
    // A protocol whose sensors ship at a documented rate has it as the default; otherwise a
    // bus must say which rate its sensors were set to.
    if (protocol->default_baud)
      bus.baud = *protocol->default_baud;
    else if (!in.has("baud"))
      in.error("baud", fmt::format("required key is missing on {} buses; {}", bus.protocol,
                                   expected));
    return;
  }
  if (std::find(rates.begin(), rates.end(), *baud) == rates.end()) {
    in.error("baud", fmt::format("{} is not a {} baud rate, {}", *baud, bus.protocol, expected));
    return;
  }
  bus.baud = std::uint32_t(*baud);
}

std::vector<std::string_view> protocols_choosing_framing(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols)
      if (protocol.bus_chooses_framing) names.push_back(protocol.name);
  return names;
}

// parity and stop_bits: only where the protocol lets a bus choose its framing. Without parity
// the default is two stop bits, so a character keeps its length (Modbus over Serial Line
// V1.02, 2.5.1); parity with two stop bits is not a framing the transport offers.
void read_framing(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol,
                  FamilyList families) {
  const auto parity = in.choice("parity", {"even", "odd", "none"});
  const auto stop_bits = in.integer("stop_bits", 1, 2);
  if (protocol == nullptr) return;
  if (!protocol->bus_chooses_framing) {
    const std::vector<std::string_view> choosing = protocols_choosing_framing(families);
    for (std::string_view key : {"parity", "stop_bits"}) {
      if (!in.has(key)) continue;
      in.error(key, choosing.empty()
                        ? fmt::format("is not accepted on {} buses (their framing is fixed)",
                                      bus.protocol)
                        : fmt::format("applies to {} buses only, not {}", or_list(choosing),
                                      bus.protocol));
    }
    return;
  }
  const Framing fallback = protocol->framing;
  const bool odd = parity ? *parity == "odd" : fallback == Framing::eight_odd_one;
  const bool none = parity ? *parity == "none"
                           : fallback == Framing::eight_none_one || fallback == Framing::eight_none_two;
  const int stops = stop_bits ? int(*stop_bits) : (none ? 2 : 1);
  if (!none && stops == 2) {
    in.error("stop_bits", "2 with parity is not supported, expected 1 (or parity = \"none\")");
    return;
  }
  bus.framing = none ? (stops == 2 ? Framing::eight_none_two : Framing::eight_none_one)
                     : (odd ? Framing::eight_odd_one : Framing::eight_even_one);
}

// gap_us: the protocol's sensors may need a minimum quiet time between master packets; some
// protocols derive the default from the baud and framing.
void read_gap(TableReader& in, BusConfig& bus, ProtocolEntry protocol) {
  constexpr std::int64_t kMaxGap = 1'000'000;
  auto us = in.integer("gap_us", 0, kMaxGap);
  if (!us) {
    if (!in.has("gap_us") && protocol.protocol != nullptr && protocol.protocol->default_gap)
      bus.gap = protocol.protocol->default_gap(bus.baud,
                                               bus.framing.value_or(protocol.protocol->framing));
    return;
  }
  if (protocol.protocol != nullptr && *us < protocol.protocol->min_gap.count()) {
    in.error("gap_us", fmt::format("{} is too short for {} sensors, expected {}..{}", *us,
                                   protocol.family->name, protocol.protocol->min_gap.count(),
                                   kMaxGap));
    return;
  }
  bus.gap = microseconds(*us);
}

// master_address: only where the protocol gives the master an address of its own.
void read_master_address(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol,
                         FamilyList families) {
  AddressRange range;
  const std::vector<std::string_view> with_master = protocols_with_master_address(families, &range);
  if (protocol != nullptr && protocol->master_addresses) range = *protocol->master_addresses;
  auto address = in.integer("master_address", range.min, range.max);
  if (!address) return;
  if (protocol != nullptr && !protocol->master_addresses)
    in.error("master_address", fmt::format("applies to {} buses only, not {}",
                                           or_list(with_master), bus.protocol));
  bus.master_address = std::uint16_t(*address);
}

// timeout_ms, the cap of the adaptive per-sensor time-out, and the quiet guard after a
// time-out. Defaults follow what is given: the cap is at least the time-out, and the guard
// covers replies up to the cap (docs/operations.md, "How the gateway behaves": late replies).
void read_reply_timeouts(TableReader& in, BusConfig& bus) {
  if (auto ms = in.integer("timeout_ms", 1, 10'000)) bus.timeout = milliseconds(*ms);
  auto max_timeout = in.integer("max_timeout_ms", 1, 10'000);
  bus.max_timeout = max_timeout ? milliseconds(*max_timeout) : std::max(bus.max_timeout, bus.timeout);
  const Located& where = in.located();
  if (max_timeout && where.usable("timeout_ms") && bus.max_timeout < bus.timeout) {
    in.error("max_timeout_ms", fmt::format("{} is less than timeout_ms {}, expected at least {}",
                                           bus.max_timeout.count(), bus.timeout.count(),
                                           bus.timeout.count()));
    bus.max_timeout = bus.timeout;
  }
  if (auto ms = in.integer("late_guard_ms", 1, 10'000)) {
    bus.late_guard = milliseconds(*ms);
  } else {
    bus.late_guard = std::max(bus.max_timeout - bus.timeout, kMinDefaultLateGuard);
  }
}

void read_reopen_backoff(TableReader& in, BusConfig& bus) {
  if (auto ms = in.integer("reopen_min_ms", 10, 600'000)) bus.reopen_min = milliseconds(*ms);
  if (auto ms = in.integer("reopen_max_ms", 10, 3'600'000)) bus.reopen_max = milliseconds(*ms);
  const Located& where = in.located();
  if (where.usable("reopen_min_ms") && where.usable("reopen_max_ms") &&
      bus.reopen_max < bus.reopen_min) {
    in.error(in.has("reopen_max_ms") ? "reopen_max_ms" : "reopen_min_ms",
             fmt::format("reopen_max_ms {} is less than reopen_min_ms {}", bus.reopen_max.count(),
                         bus.reopen_min.count()));
  }
}

// pass_through: unit ids forwarded to the device with that address, where the protocol can
// forward Modbus requests. Checks across buses and sensors are in pass_through_checks.cpp.
void read_pass_through(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol) {
  // Modbus unit ids and slave addresses share 1..247 (0 broadcasts, 248..255 are reserved).
  const auto ids = in.integers("pass_through", 1, 247);
  if (!ids) return;
  if (protocol != nullptr && protocol->forward == nullptr) {
    in.error("pass_through",
             fmt::format("protocol {} cannot forward Modbus requests", bus.protocol));
    return;
  }
  for (std::size_t i = 0; i < ids->size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if ((*ids)[j] != (*ids)[i]) continue;
      in.error("pass_through", fmt::format("unit id {} is listed twice", (*ids)[i]));
      bus.pass_through.clear();
      return;
    }
    bus.pass_through.push_back(std::uint8_t((*ids)[i]));
  }
}

}  // namespace

ParsedBus read_bus(const toml::table& table, std::string path, ErrorList& errors,
                   FamilyList families) {
  TableReader in(table, std::move(path), errors);
  BusConfig bus;
  bus.line = in.located().header().line;
  if (auto name = in.string("name", Presence::required)) {
    check_name(in, "name", *name);
    bus.name = *name;
  }
  const std::optional<PortAddress> port = read_port(in, bus);
  const std::vector<std::string_view> protocols = protocol_names(families);
  bus.protocol = protocols.empty() ? "" : std::string(protocols.front());
  if (auto protocol = in.choice("protocol", protocols)) bus.protocol = *protocol;
  const ProtocolEntry protocol = in.located().usable("protocol")
                                     ? find_protocol(families, bus.protocol)
                                     : ProtocolEntry{};
  read_reply_timeouts(in, bus);
  if (auto n = in.integer("retries", 0, 10)) bus.retries = int(*n);
  if (devices_speak_tcp(protocol)) {
    refuse_serial_line_keys(in, protocol);
    // No serial line: no wire time (baud 0) and no quiet time between requests.
    bus.baud = 0;
    bus.gap = std::chrono::microseconds{0};
  } else {
    read_baud(in, bus, protocol.protocol);
    read_framing(in, bus, protocol.protocol, families);
    read_gap(in, bus, protocol);
    if (auto rs485 = in.boolean("rs485")) bus.rs485_kernel = *rs485;
    if (auto echo = in.boolean("echo")) bus.echo = *echo;
  }
  // Ignored on a device server's port (no tty of ours to set it on).
  if (auto low_latency = in.boolean("low_latency")) bus.low_latency = *low_latency;
  read_master_address(in, bus, protocol.protocol, families);
  read_reopen_backoff(in, bus);
  read_pass_through(in, bus, protocol.protocol);
  if (port) check_port_fits(in, bus, *port, protocol);
  // Checked against [server] and the other buses in listeners.cpp.
  if (auto port = in.integer("tcp_port", 1, 65535)) bus.tcp_port = std::uint16_t(*port);
  if (auto seconds = in.integer("black_box_s", 1, 3600)) bus.black_box = std::chrono::seconds(*seconds);
  in.reject_unknown_keys();
  return ParsedBus{std::move(bus), in.located()};
}

}  // namespace tiltgate::config
