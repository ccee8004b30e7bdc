// Whether a request's Host header names this gateway
// (docs/web-console.md, "Headers and host names"). A page of another site whose name a DNS
// server turns into this gateway's address ("DNS rebinding") reaches the gateway from the user's browser with that site's name in
// Host, and the browser takes the answers as that site's own: a request whose Host names none of
// [http] server_names is answered 421 and never reaches a route. Pure: no I/O, no DNS.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

enum class HostVerdict {
  ours,     // one of the server names, or the address the request came in on
  missing,  // no Host header, or an empty one: 400
  other,    // another name or address: 421
};

// `host` is the Host header as sent ("gw.example:8080", "[fd00::5]:8080"); `names` as
// HttpServerOptions::server_names; `local_address` the address the connection came in on: an
// address literal naming it is always ours (a browser sends a name it looked up, never an
// address it did not connect to). Names compare without regard to case or a trailing dot; the
// port is not compared.
HostVerdict check_host(std::string_view host, std::span<const std::string> names,
                       std::string_view local_address);

// The names a request may give when [http] server_names is not written: `listen` unless it is
// the wildcard address, "localhost" and the machine's name `machine` with its first label alone
// ("gw-3.plant.example" and "gw-3").
std::vector<std::string> default_server_names(std::string_view listen, std::string_view machine);

}  // namespace tiltgate
