// A [[bus]] port as written in the configuration or given to --port: a local tty path, or a
// serial device server reached over the network (docs/operations.md, "Serial device servers"):
//   tcp://HOST:PORT      raw TCP: the server passes bytes; rate and framing are set on it.
//   rfc2217://HOST:PORT  Telnet with the COM-PORT-OPTION (RFC 2217): the gateway sets the far
//                        port's rate and framing from the bus's keys.
// HOST is a name, an IPv4 address or an IPv6 address in brackets ([fe80::1]). Parsing only:
// nothing here resolves a name or connects (names resolve at each connect).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

enum class PortScheme : std::uint8_t { tty, tcp, rfc2217 };

struct PortAddress {
  PortScheme scheme = PortScheme::tty;
  std::string path;  // the tty's path (scheme tty)
  std::string host;  // the server's name or address, without brackets (tcp, rfc2217)
  std::uint16_t port = 0;

  bool over_network() const { return scheme != PortScheme::tty; }
  // "host:port" (an IPv6 address in brackets), the key two buses may not share.
  std::string endpoint() const;
};

// Whether `text` is written as a URL ("letters://..."): then it must parse as one, and a typo
// in the scheme is an error rather than a tty path.
bool looks_like_url(std::string_view text);

// The port `text` names. A URL must be tcp:// or rfc2217:// with a host and a port 1..65535 and
// nothing after it; anything else not written as a URL is a tty path. The error says what is
// wrong in words a controls engineer can act on.
Expected<PortAddress, std::string> parse_port(std::string_view text);

}  // namespace tiltgate
