#include "control/peer_identity.h"

#include <fmt/format.h>
#include <pwd.h>
#include <sys/socket.h>

#include <vector>

namespace tiltgate {

std::optional<uid_t> peer_uid(int socket_fd) {
  ucred peer{};
  socklen_t size = sizeof peer;
  if (::getsockopt(socket_fd, SOL_SOCKET, SO_PEERCRED, &peer, &size) != 0 || size != sizeof peer)
    return std::nullopt;
  return peer.uid;
}

std::string peer_identity(int socket_fd) {
  ucred peer{};
  socklen_t size = sizeof peer;
  if (::getsockopt(socket_fd, SOL_SOCKET, SO_PEERCRED, &peer, &size) != 0 || size != sizeof peer)
    return "an unknown process";
  std::vector<char> buffer(16384);
  passwd entry{};
  passwd* found = nullptr;
  getpwuid_r(peer.uid, &entry, buffer.data(), buffer.size(), &found);
  if (found == nullptr) return fmt::format("uid {} (pid {})", peer.uid, peer.pid);
  return fmt::format("user {} (uid {}, pid {})", found->pw_name, peer.uid, peer.pid);
}

}  // namespace tiltgate
