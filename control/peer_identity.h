// Who is at the other end of a control-socket connection: the Unix user and process the kernel
// recorded when it connected (SO_PEERCRED), for the log line of what the connection changes.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace tiltgate {

// "user root (uid 0, pid 4242)"; "uid 1234 (pid 4242)" for a uid without a name; "an unknown
// process" when the kernel cannot say (not a Unix socket).
std::string peer_identity(int socket_fd);
// The peer's uid; none when the kernel cannot say.
std::optional<uid_t> peer_uid(int socket_fd);

}  // namespace tiltgate
