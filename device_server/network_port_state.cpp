#include "device_server/network_port_state.h"

namespace tiltgate {

namespace {

using namespace network_port_state;
using Event = NetworkPortEvent;

// A connect under way (Opening or Reconnecting) on a deadline's event: the same state, with
// the deadline armed afresh or passed.
template <typename Connecting>
std::optional<NetworkPortState> on_deadline(Connecting connecting, Event event) {
  if (event == Event::deadline_armed) connecting.deadline_passed = false;
  else connecting.deadline_passed = true;
  return connecting;
}

bool is_deadline(Event event) {
  return event == Event::deadline_armed || event == Event::deadline_passed;
}

}  // namespace

std::optional<NetworkPortState> next_state(const NetworkPortState& state, Event event) {
  if (event == Event::stop_asked) {
    if (std::holds_alternative<Stopped>(state)) return std::nullopt;
    return Stopped{};
  }
  if (std::holds_alternative<Closed>(state)) {
    if (event == Event::open_asked) return Opening{};
    // A port lost before it was opened is connected as one lost when open.
    if (event == Event::lost) return Reconnecting{};
    return std::nullopt;
  }
  if (const auto* opening = std::get_if<Opening>(&state)) {
    if (event == Event::attempt_failed) return Reconnecting{};
    if (event == Event::connected) return Open{};
    if (is_deadline(event)) return on_deadline(*opening, event);
    return std::nullopt;  // lost: the attempt under way goes on
  }
  if (const auto* reconnecting = std::get_if<Reconnecting>(&state)) {
    if (event == Event::attempt_failed) return Reconnecting{};  // the next attempt, afresh
    if (event == Event::connected) return Open{};
    if (is_deadline(event)) return on_deadline(*reconnecting, event);
    return std::nullopt;
  }
  if (std::holds_alternative<Open>(state)) {
    if (event == Event::lost) return Reconnecting{};
    return std::nullopt;
  }
  return std::nullopt;  // Stopped
}

bool NetworkPortStates::deadline_passed() const {
  if (const auto* opening = std::get_if<Opening>(&state_)) return opening->deadline_passed;
  if (const auto* reconnecting = std::get_if<Reconnecting>(&state_))
    return reconnecting->deadline_passed;
  return false;
}

bool NetworkPortStates::on(Event event) {
  std::optional<NetworkPortState> next = next_state(state_, event);
  if (!next) return false;
  state_ = std::move(*next);
  return true;
}

}  // namespace tiltgate
