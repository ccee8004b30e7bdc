// Which client addresses may connect or write ([server] allow, write_allow; [http] allow):
// addresses and CIDR blocks, IPv4 and IPv6. An IPv4 client of a dual-stack socket
// (::ffff:a.b.c.d) is its IPv4 address, so it matches IPv4 rules. Pure (inet_pton only): the
// config checks entries with it, the servers match peers with it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

// 16 bytes; an IPv4 address in its IPv4-mapped IPv6 form (::ffff:a.b.c.d).
using IpAddressBytes = std::array<std::uint8_t, 16>;

// "10.0.0.5", "::1", "::ffff:10.0.0.5" (the same as "10.0.0.5"); none if not an address.
std::optional<IpAddressBytes> parse_ip_address(std::string_view text);

// One entry: an address, or a network as address/prefix-length.
struct AddressRule {
  IpAddressBytes network{};
  int prefix_bits = 128;  // of the 16 bytes: an IPv4 /8 is 96 + 8
  std::string text;       // as written

  bool operator==(const AddressRule&) const = default;
};

// "10.0.0.0/8", "192.168.1.20", "::1", "fd00::/8"; the error says what is wrong with it.
Expected<AddressRule, std::string> parse_address_rule(std::string_view entry);

class AddressAllowList {
 public:
  AddressAllowList() = default;  // everyone
  // Each entry a rule (an empty list allows nobody); the error names the first bad entry.
  static Expected<AddressAllowList, std::string> parse(std::span<const std::string> entries);

  bool allows(const IpAddressBytes& address) const;
  // A peer's address as text (what the servers have); nothing that is not an address is
  // allowed unless everyone is.
  bool allows(std::string_view address) const;
  bool allows_everyone() const { return !rules_.has_value(); }
  // The entries as written; empty when everyone is allowed.
  std::vector<std::string> entries() const;

  bool operator==(const AddressAllowList&) const = default;

 private:
  std::optional<std::vector<AddressRule>> rules_;  // none: everyone
};

}  // namespace tiltgate
