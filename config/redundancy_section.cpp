// [redundancy]: this gateway's half of a warm standby pair on the same lines
// (docs/configuration.md, "[redundancy]"). Its takeover_ms is checked against the buses' polls
// in redundancy_checks.cpp, once every table is read.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <string>
#include <string_view>

#include "config/host_names.h"
#include "config/sections.h"
#include "driver/expected.h"
#include "driver/visible_text.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::Presence;

namespace {

// What every peer error ends with, so the fix is in front of the reader.
constexpr std::string_view kPeerForm =
    "expected the other gateway's Modbus TCP address as \"HOST:PORT\", e.g. \"10.0.0.12:502\", "
    "\"gw-b.plant.example:502\" or \"[fd00::12]:502\"";

struct PeerAddress {
  std::string host;  // a name or an address, an IPv6 one without its brackets
  std::uint16_t port = 0;
};

// An IPv6 address, with a zone ("fe80::12%eth0") for a link-local peer.
bool is_peer_ipv6(std::string_view text) {
  const std::size_t percent = text.find('%');
  if (percent == std::string_view::npos) return is_ipv6_address(std::string(text));
  const std::string_view zone = text.substr(percent + 1);
  const bool zone_ok = !zone.empty() && std::all_of(zone.begin(), zone.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
  });
  return zone_ok && is_ipv6_address(std::string(text.substr(0, percent)));
}

// The digits after the host's ':'.
Expected<std::uint16_t, std::string> parse_peer_port(std::string_view digits) {
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (digits.empty() || ec == std::errc::invalid_argument ||
      end != digits.data() + digits.size())
    return Unexpected(fmt::format("the port \"{}\" is not a number, expected 1..65535",
                                  visible_text(digits)));
  if (ec == std::errc::result_out_of_range || value < 1 || value > 65535)
    return Unexpected(fmt::format("the port {} is out of range, expected 1..65535", digits));
  return std::uint16_t(value);
}

// "HOST:PORT", "[IPV6]:PORT". Syntax only: a name is resolved where it is used.
Expected<PeerAddress, std::string> parse_peer(std::string_view text) {
  const std::string shown = visible_text(text);
  if (text.empty()) return Unexpected(fmt::format("empty, {}", kPeerForm));
  if (text.find("://") != std::string_view::npos)
    return Unexpected(fmt::format("\"{}\" has a scheme; {}", shown, kPeerForm));
  PeerAddress peer;
  std::string_view rest;
  if (text.front() == '[') {
    const std::size_t close = text.find(']');
    if (close == std::string_view::npos)
      return Unexpected(fmt::format("\"{}\": an IPv6 address needs its closing ']'; {}", shown,
                                    kPeerForm));
    const std::string_view host = text.substr(1, close - 1);
    if (!is_peer_ipv6(host))
      return Unexpected(fmt::format("\"{}\": \"{}\" in brackets is not an IPv6 address; {}",
                                    shown, visible_text(host), kPeerForm));
    peer.host = std::string(host);
    rest = text.substr(close + 1);
  } else {
    const std::size_t colon = text.find(':');
    // Two colons or more: an IPv6 address, whose own colons would swallow the port.
    if (colon != std::string_view::npos && text.find(':', colon + 1) != std::string_view::npos)
      return Unexpected(fmt::format("\"{}\": an IPv6 address is written in brackets, before "
                                    "its port; {}",
                                    shown, kPeerForm));
    const std::string host(text.substr(0, colon));
    if (host.empty()) return Unexpected(fmt::format("\"{}\" has no host; {}", shown, kPeerForm));
    if (!is_ip_address(host) && !is_host_name(host))
      return Unexpected(fmt::format("\"{}\": \"{}\" is not a host name or an IP address; {}",
                                    shown, visible_text(host), kPeerForm));
    peer.host = host;
    rest = colon == std::string_view::npos ? std::string_view{} : text.substr(colon);
  }
  // The port is the peer's [server] port, which is rarely 502 on both sides of a test bench:
  // never assumed.
  if (rest.empty())
    return Unexpected(fmt::format("\"{}\" has no port; {}", shown, kPeerForm));
  if (rest.front() != ':')
    return Unexpected(fmt::format("\"{}\": unexpected \"{}\" after the host; {}", shown,
                                  visible_text(rest), kPeerForm));
  auto port = parse_peer_port(rest.substr(1));
  if (!port) return Unexpected(port.error());
  peer.port = *port;
  return peer;
}

void read_peer(TableReader& in, RedundancyConfig& redundancy) {
  if (!in.has("peer")) {
    in.string("peer");  // asked for, so that it is a known key
    return in.error("peer", fmt::format("required key is missing; {}", kPeerForm));
  }
  const auto text = in.string("peer");
  if (!text) return;
  auto peer = parse_peer(*text);
  if (!peer) return in.error("peer", peer.error());
  redundancy.peer_host = std::move(peer->host);
  redundancy.peer_port = peer->port;
}

}  // namespace

ParsedRedundancy read_redundancy(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "redundancy", errors);
  RedundancyConfig redundancy;
  // Required with the table: the same file on both gateways differs by this key, and a pair
  // where neither says which it is would have two masters on the line.
  if (auto role = in.choice("role", {"primary", "standby"}, Presence::required))
    redundancy.role = *role == "primary" ? RedundancyConfig::Role::primary
                                         : RedundancyConfig::Role::standby;
  read_peer(in, redundancy);
  // The bounds catch a value meant in seconds ("2") or in microseconds; whether it outlasts
  // each line's quiet between the primary's requests is checked with the buses
  // (redundancy_checks.cpp).
  if (auto ms = in.integer("takeover_ms", 200, 60000))
    redundancy.takeover = std::chrono::milliseconds(*ms);
  if (auto failback = in.boolean("failback")) redundancy.failback = *failback;
  in.reject_unknown_keys();
  return ParsedRedundancy{std::move(redundancy), in.located()};
}

}  // namespace tiltgate::config
