#include "control/control_socket_io.h"

#include <cerrno>
#include <cstring>
#include <poll.h>
#include <sys/socket.h>

#include "control/control_protocol.h"

namespace tiltgate::control {

namespace {

// Waits until `fd` is ready for `events`; false when the deadline passed or it failed.
bool wait_ready(int fd, short events, Deadline deadline) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, int(left.count()));
    if (n > 0) return (p.revents & (POLLERR | POLLNVAL)) == 0;
    if (n < 0 && errno != EINTR) return false;
  }
}

bool would_block(int error) { return error == EAGAIN || error == EWOULDBLOCK || error == EINTR; }

}  // namespace

Expected<Done, std::string> send_line(int fd, const std::string& line, Deadline deadline) {
  const std::string text = line + "\n";
  std::size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n =
        ::send(fd, text.data() + sent, text.size() - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += std::size_t(n);
      continue;
    }
    if (n < 0 && !would_block(errno)) return Unexpected{std::string(std::strerror(errno))};
    if (!wait_ready(fd, POLLOUT, deadline)) return Unexpected{std::string("the peer did not read")};
  }
  return Done{};
}

Expected<std::string, std::string> read_line(int fd, Deadline deadline) {
  std::string line;
  while (line.size() < kMaxLine) {
    char c = 0;
    const ssize_t n = ::recv(fd, &c, 1, MSG_DONTWAIT);
    if (n == 1) {
      if (c == '\n') return line;
      line += c;
      continue;
    }
    if (n == 0) return Unexpected{std::string("the connection was closed")};
    if (!would_block(errno)) return Unexpected{std::string(std::strerror(errno))};
    if (!wait_ready(fd, POLLIN, deadline)) return Unexpected{std::string("no answer in time")};
  }
  return Unexpected{std::string("the answer is too long")};
}

}  // namespace tiltgate::control
