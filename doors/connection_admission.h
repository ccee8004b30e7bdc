// Whom a new TCP connection may displace when a server is full (docs/operations.md, "How the
// gateway behaves"): idle connections are cheap to open and hold, so a full server replaces the
// one idle longest rather than turn a PLC (or the HTTP status page's reader) away, and one
// address may hold only so many. Pure: the server describes its connections, this decides.
// Used by the Modbus TCP server and the HTTP server (http/http_server.h).
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace tiltgate {

// One open connection as admission sees it.
struct OpenConnection {
  std::string_view address;  // the peer's address without its port (canonical_address())
  // Between requests (waiting for the next one to start); a connection mid-request, waiting
  // on its handler or sending its reply is never replaced.
  bool idle = false;
  std::chrono::steady_clock::time_point idle_since{};  // its last request finished, or it connected
  // Idle connections that give way before all others (oldest first among them): HTTP's
  // kept-alive connections between requests, whose client reconnects at no cost.
  bool gives_way_first = false;
};

struct AdmissionLimits {
  std::size_t max_clients = 32;
  std::size_t max_clients_per_host = 8;
};

enum class AdmissionLimit { none, max_clients, max_clients_per_host };

struct Admission {
  bool admitted = false;
  // The connection (an index into what was passed) to close for the new one, if any.
  std::optional<std::size_t> replaced;
  AdmissionLimit limit = AdmissionLimit::none;  // the limit reached, when one was
};

// A new connection from `address`: admitted at once below both limits; at its address's limit
// it replaces that address's own connection idle longest, else is refused; at max_clients it
// replaces the connection idle longest of any address, else is refused. "Idle longest" puts
// those that give way first before the others.
Admission admit_connection(std::span<const OpenConnection> open, std::string_view address,
                           AdmissionLimits limits);

}  // namespace tiltgate
