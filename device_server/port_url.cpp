#include "device_server/port_url.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace tiltgate {

namespace {

constexpr std::string_view kSchemeEnd = "://";

bool is_scheme_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
}

// Letters, digits, '-', '.' and '_' (names), ':' only inside brackets (IPv6).
bool is_host_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
}

}  // namespace

std::string PortAddress::endpoint() const {
  if (host.find(':') != std::string::npos) return "[" + host + "]:" + std::to_string(port);
  return host + ":" + std::to_string(port);
}

bool looks_like_url(std::string_view text) {
  const std::size_t end = text.find(kSchemeEnd);
  if (end == std::string_view::npos || end == 0) return false;
  return std::all_of(text.begin(), text.begin() + std::ptrdiff_t(end), is_scheme_char);
}

Expected<PortAddress, std::string> parse_port(std::string_view text) {
  if (text.empty()) {
    return Unexpected(std::string(
        "empty, expected a tty path such as \"/dev/ttyUSB0\" or a device server such as "
        "\"tcp://192.168.1.20:4001\""));
  }
  if (!looks_like_url(text)) {
    PortAddress tty;
    tty.path = std::string(text);
    return tty;
  }
  const std::size_t scheme_end = text.find(kSchemeEnd);
  const std::string_view scheme = text.substr(0, scheme_end);
  PortAddress address;
  if (scheme == "tcp") {
    address.scheme = PortScheme::tcp;
  } else if (scheme == "rfc2217") {
    address.scheme = PortScheme::rfc2217;
  } else {
    return Unexpected("unknown scheme \"" + std::string(scheme) +
                      "://\", expected tcp:// (raw TCP) or rfc2217:// (Telnet COM-PORT-OPTION)");
  }
  std::string_view rest = text.substr(scheme_end + kSchemeEnd.size());
  std::string_view host;
  if (!rest.empty() && rest.front() == '[') {
    const std::size_t close = rest.find(']');
    if (close == std::string_view::npos) {
      return Unexpected(std::string("an IPv6 address needs its closing ']', as in tcp://[fe80::1]:4001"));
    }
    host = rest.substr(1, close - 1);
    const bool ipv6_chars = std::all_of(host.begin(), host.end(), [](char c) {
      return std::isxdigit(static_cast<unsigned char>(c)) || c == ':' || c == '.' || c == '%';
    });
    if (host.empty() || !ipv6_chars) {
      return Unexpected("\"" + std::string(host) + "\" is not an IPv6 address");
    }
    rest = rest.substr(close + 1);
  } else {
    const std::size_t colon = rest.find(':');
    host = rest.substr(0, colon);
    rest = colon == std::string_view::npos ? std::string_view{} : rest.substr(colon);
    if (host.empty()) {
      return Unexpected("no host, expected " + std::string(scheme) + "://HOST:PORT");
    }
    if (!std::all_of(host.begin(), host.end(), is_host_char)) {
      return Unexpected("\"" + std::string(host) +
                        "\" is not a host name or address (letters, digits, '-', '.')");
    }
  }
  if (rest.empty() || rest.front() != ':') {
    return Unexpected("no port, expected " + std::string(scheme) + "://" + std::string(host) +
                      ":PORT (the device server's TCP port, 1..65535)");
  }
  const std::string_view digits = rest.substr(1);
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (digits.empty() || ec == std::errc::invalid_argument) {
    return Unexpected("the port \"" + std::string(digits) + "\" is not a number 1..65535");
  }
  if (end != digits.data() + digits.size()) {
    return Unexpected("unexpected \"" + std::string(end, digits.data() + digits.size()) +
                      "\" after the port, expected " + std::string(scheme) + "://HOST:PORT");
  }
  if (ec == std::errc::result_out_of_range || value < 1 || value > 65535) {
    return Unexpected("the port " + std::string(digits) + " is out of range, expected 1..65535");
  }
  address.host = std::string(host);
  address.port = std::uint16_t(value);
  return address;
}

}  // namespace tiltgate
