#include "http/host_check.h"

#include <boost/asio/ip/address.hpp>

#include <algorithm>
#include <cctype>
#include <optional>

namespace tiltgate {

namespace {

// The host without its port or an IPv6 literal's brackets, lower case, no trailing dot.
std::string host_part(std::string_view host) {
  std::string_view name = host;
  if (name.starts_with('[')) {
    const auto end = name.find(']');
    name = end == std::string_view::npos ? name.substr(1) : name.substr(1, end - 1);
  } else if (name.find(':') == name.rfind(':') && name.find(':') != std::string_view::npos) {
    name = name.substr(0, name.find(':'));  // one colon: name:port (two or more: a bare IPv6)
  }
  if (name.ends_with('.')) name.remove_suffix(1);
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return lower;
}

// The address `text` names (an IPv4-mapped IPv6 address as its IPv4 one), or none.
std::optional<boost::asio::ip::address> address_of(std::string_view text) {
  boost::system::error_code ec;
  auto address = boost::asio::ip::make_address(std::string(text), ec);
  if (ec) return std::nullopt;
  if (address.is_v6() && address.to_v6().is_v4_mapped())
    return boost::asio::ip::address(
        boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, address.to_v6()));
  return address;
}

}  // namespace

HostVerdict check_host(std::string_view host, std::span<const std::string> names,
                       std::string_view local_address) {
  const std::string asked = host_part(host);
  if (asked.empty()) return HostVerdict::missing;
  for (const std::string& name : names)
    if (host_part(name) == asked) return HostVerdict::ours;
  const auto address = address_of(asked);
  if (address && address == address_of(local_address)) return HostVerdict::ours;
  // A name that is an address: compared as addresses ("::1" and "0:0:0:0:0:0:0:1").
  if (address)
    for (const std::string& name : names)
      if (address == address_of(host_part(name))) return HostVerdict::ours;
  return HostVerdict::other;
}

std::vector<std::string> default_server_names(std::string_view listen, std::string_view machine) {
  std::vector<std::string> names;
  const auto address = address_of(listen);
  if (!address || !address->is_unspecified()) names.emplace_back(listen);
  names.emplace_back("localhost");
  if (!machine.empty()) {
    names.emplace_back(machine);
    if (const auto dot = machine.find('.'); dot != std::string_view::npos && dot > 0)
      names.emplace_back(machine.substr(0, dot));
  }
  return names;
}

}  // namespace tiltgate
