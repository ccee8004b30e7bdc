// How a host is written in the configuration: an IP address literal, or a DNS name. Syntax
// only: nothing is resolved (a name resolves where it is used, at each connect).
#pragma once

#include <string>
#include <string_view>

namespace tiltgate::config {

// An IPv4 or IPv6 address literal ("10.0.0.5", "fd00::5"), without brackets or zone.
bool is_ip_address(const std::string& text);
bool is_ipv6_address(const std::string& text);

// A DNS host name: dot-separated labels of letters, digits and '-' (RFC 1123, 2.1).
bool is_host_name(std::string_view text);

}  // namespace tiltgate::config
