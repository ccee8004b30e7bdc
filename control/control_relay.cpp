#include "control/control_relay.h"

#include <variant>

#include "control/control_protocol.h"
#include "control/control_socket_io.h"

namespace tiltgate {

bool ControlRelayFramer::send_line(const std::string& line) {
  return control::send_line(fd_, line, std::chrono::steady_clock::now() + kAnswerWait).has_value();
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
  if (const auto answer = control::read_line(fd_, std::chrono::steady_clock::now() + kAnswerWait))
    if (const auto parsed = control::parse_command(*answer))
      if (const auto* verdict = std::get_if<control::FramerAnswer>(&*parsed)) return verdict->done;
  broken_ = true;  // gone, too slow, or not an answer
  return false;
}

}  // namespace tiltgate
