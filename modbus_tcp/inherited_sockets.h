// Listening sockets handed over by systemd (socket activation, sd_listen_fds(3)): a
// tiltgate.socket unit binds port 502 as root and the gateway, started without any privilege,
// serves on it.
#pragma once

#include <cstdint>
#include <optional>

namespace tiltgate {

struct InheritedListener {
  int fd = -1;
  bool ipv6 = false;
};

// The inherited listening TCP socket bound to `port`, taken: each is handed out once. None when
// systemd passed none for that port (or the process was not socket-activated). Port 0 (any
// free port) never matches.
std::optional<InheritedListener> take_inherited_listener(std::uint16_t port);

}  // namespace tiltgate
