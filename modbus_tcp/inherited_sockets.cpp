#include "modbus_tcp/inherited_sockets.h"

#include <sys/socket.h>
#include <systemd/sd-daemon.h>

#include <algorithm>
#include <vector>

namespace tiltgate {

namespace {

// Read once: sd_listen_fds(1) also clears LISTEN_FDS and LISTEN_PID from the environment, so
// a child process (a simulator in the demo) does not take the sockets for its own.
std::vector<int>& unclaimed() {
  static std::vector<int> fds = [] {
    std::vector<int> passed;
    const int n = sd_listen_fds(1);
    for (int i = 0; i < n; ++i) passed.push_back(SD_LISTEN_FDS_START + i);
    return passed;
  }();
  return fds;
}

}  // namespace

std::optional<InheritedListener> take_inherited_listener(std::uint16_t port) {
  if (port == 0) return std::nullopt;
  std::vector<int>& fds = unclaimed();
  for (auto it = fds.begin(); it != fds.end(); ++it) {
    const int fd = *it;
    for (const int family : {AF_INET, AF_INET6}) {
      if (sd_is_socket_inet(fd, family, SOCK_STREAM, 1, port) > 0) {
        fds.erase(it);
        return InheritedListener{fd, family == AF_INET6};
      }
    }
  }
  return std::nullopt;
}

}  // namespace tiltgate
