#include "gateway/control_relay.h"

#include <cerrno>
#include <poll.h>
#include <sys/socket.h>
#include <variant>

#include "gateway/control_protocol.h"

namespace tiltgate {

namespace {

using Clock = std::chrono::steady_clock;

// Waits until `fd` is ready for `events` or `deadline` passes.
bool wait_ready(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, int(left.count()));
    if (n > 0) return (p.revents & (POLLERR | POLLNVAL)) == 0;
    if (n < 0 && errno != EINTR) return false;
  }
}

// One line from the command, without its newline; empty when none came in time.
std::string read_line(int fd, Clock::time_point deadline) {
  std::string line;
  while (line.size() < control::kMaxLine) {
    char c = 0;
    const ssize_t n = ::recv(fd, &c, 1, MSG_DONTWAIT);
    if (n == 1) {
      if (c == '\n') return line;
      line += c;
      continue;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) return {};
    if (!wait_ready(fd, POLLIN, deadline)) return {};
  }
  return {};
}

}  // namespace

bool ControlRelayFramer::send_line(const std::string& line) {
  const std::string text = line + "\n";
  const Clock::time_point deadline = Clock::now() + kAnswerWait;
  std::size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = ::send(fd_, text.data() + sent, text.size() - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += std::size_t(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return false;
    if (!wait_ready(fd_, POLLOUT, deadline)) return false;
  }
  return true;
}

void ControlRelayFramer::reset() {
  if (!broken_ && !send_line(control::format(control::GatewayMessage{control::Reset{}})))
    broken_ = true;
}

bool ControlRelayFramer::feed(std::span<const std::uint8_t> bytes) {
  if (broken_ || bytes.empty()) return false;
  const control::Received received{{bytes.begin(), bytes.end()}};
  if (!send_line(control::format(control::GatewayMessage{received}))) {
    broken_ = true;
    return false;
  }
  const std::string answer = read_line(fd_, Clock::now() + kAnswerWait);
  const auto parsed = control::parse_command(answer);
  const auto* verdict = parsed ? std::get_if<control::FramerAnswer>(&*parsed) : nullptr;
  if (verdict == nullptr) {
    broken_ = true;
    return false;
  }
  return verdict->done;
}

}  // namespace tiltgate
