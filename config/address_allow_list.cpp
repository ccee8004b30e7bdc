#include "config/address_allow_list.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>

namespace tiltgate {

namespace {

struct ParsedAddress {
  IpAddressBytes bytes{};
  bool v4 = false;  // written as IPv4: its prefix counts from byte 12
};

std::optional<ParsedAddress> parse(std::string_view text) {
  const std::string z(text);  // inet_pton needs the terminator
  ParsedAddress parsed;
  std::array<std::uint8_t, 4> v4{};
  if (inet_pton(AF_INET, z.c_str(), v4.data()) == 1) {
    parsed.bytes[10] = parsed.bytes[11] = 0xFF;
    std::copy(v4.begin(), v4.end(), parsed.bytes.begin() + 12);
    parsed.v4 = true;
    return parsed;
  }
  if (inet_pton(AF_INET6, z.c_str(), parsed.bytes.data()) == 1) return parsed;
  return std::nullopt;
}

bool in_network(const IpAddressBytes& address, const IpAddressBytes& network, int prefix_bits) {
  for (int bit = 0; bit < prefix_bits; ++bit) {
    const int byte = bit / 8;
    const std::uint8_t mask = std::uint8_t(0x80 >> (bit % 8));
    if ((address[std::size_t(byte)] & mask) != (network[std::size_t(byte)] & mask)) return false;
  }
  return true;
}

}  // namespace

std::optional<IpAddressBytes> parse_ip_address(std::string_view text) {
  const auto parsed = parse(text);
  if (!parsed) return std::nullopt;
  return parsed->bytes;
}

Expected<AddressRule, std::string> parse_address_rule(std::string_view entry) {
  const auto slash = entry.find('/');
  const std::string_view address_text = entry.substr(0, slash);
  const auto address = parse(address_text);
  if (!address)
    return Unexpected(fmt::format("\"{}\": \"{}\" is not an IPv4 or IPv6 address", entry,
                                  address_text));
  AddressRule rule;
  rule.network = address->bytes;
  rule.text = std::string(entry);
  if (slash == std::string_view::npos) return rule;  // one address: every bit counts

  const int max_bits = address->v4 ? 32 : 128;
  const std::string_view length_text = entry.substr(slash + 1);
  int length = -1;
  const auto [end, ec] =
      std::from_chars(length_text.data(), length_text.data() + length_text.size(), length);
  if (length_text.empty() || ec != std::errc{} || end != length_text.data() + length_text.size() ||
      length < 0 || length > max_bits)
    return Unexpected(fmt::format("\"{}\": the prefix length must be 0..{}", entry, max_bits));
  rule.prefix_bits = (address->v4 ? 96 : 0) + length;
  // "10.0.0.1/8" is most likely a typing error for one address or for 10.0.0.0/8.
  for (int bit = rule.prefix_bits; bit < 128; ++bit)
    if (rule.network[std::size_t(bit / 8)] & (0x80 >> (bit % 8)))
      return Unexpected(fmt::format("\"{}\": bits are set past the /{} prefix (a network is "
                                    "written with them zero, e.g. \"10.0.0.0/8\")",
                                    entry, length));
  return rule;
}

Expected<AddressAllowList, std::string> AddressAllowList::parse(
    std::span<const std::string> entries) {
  AddressAllowList list;
  list.rules_.emplace();
  for (const std::string& entry : entries) {
    auto rule = parse_address_rule(entry);
    if (!rule) return Unexpected(rule.error());
    list.rules_->push_back(std::move(*rule));
  }
  return list;
}

bool AddressAllowList::allows(const IpAddressBytes& address) const {
  if (!rules_) return true;
  for (const AddressRule& rule : *rules_)
    if (in_network(address, rule.network, rule.prefix_bits)) return true;
  return false;
}

bool AddressAllowList::allows(std::string_view address) const {
  if (!rules_) return true;
  const auto parsed = parse_ip_address(address);
  return parsed && allows(*parsed);
}

std::vector<std::string> AddressAllowList::entries() const {
  std::vector<std::string> texts;
  if (rules_)
    for (const AddressRule& rule : *rules_) texts.push_back(rule.text);
  return texts;
}

}  // namespace tiltgate
