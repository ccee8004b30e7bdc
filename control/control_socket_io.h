// Blocking, deadline-bounded line I/O on a control-socket descriptor, for a command's handshake
// before its event loop runs (control/gateway_command.h).
// Lines are control_protocol.h's, without the newline.
#pragma once

#include <chrono>
#include <string>

#include "driver/expected.h"

namespace tiltgate::control {

using Deadline = std::chrono::steady_clock::time_point;

// Sends `line` and a newline; an error when the peer is gone or the deadline passed.
Expected<Done, std::string> send_line(int fd, const std::string& line, Deadline deadline);
// Reads one line; an error when the peer closed, the deadline passed or the line is too long.
Expected<std::string, std::string> read_line(int fd, Deadline deadline);

}  // namespace tiltgate::control
