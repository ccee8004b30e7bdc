// The states of a line's port on a serial device server (device_server/network_port.h) and the
// only moves between them, in one place: a state is one value, so a port cannot be open and
// stopped at once, and the connect deadline exists only while a connect is under way.
// Pure: no socket, no timer.
#pragma once

#include <optional>
#include <variant>

namespace tiltgate {

namespace network_port_state {

struct Closed {  // made, not opened yet
  bool operator==(const Closed&) const = default;
};
// open()'s first connect attempt is under way: an exchange waits for it (LinePort::opening()).
struct Opening {
  bool deadline_passed = false;  // connect_timeout passed in this attempt's current step
  bool operator==(const Opening&) const = default;
};
// Connecting again, with back-off, after a failed attempt or a lost connection; the outage has
// been logged as a warning once, each later failure only at debug.
struct Reconnecting {
  bool deadline_passed = false;  // as Opening's
  bool operator==(const Reconnecting&) const = default;
};
struct Open {  // connected and, over RFC 2217, the far port's settings confirmed
  bool operator==(const Open&) const = default;
};
struct Stopped {  // stop(): closed for good
  bool operator==(const Stopped&) const = default;
};

}  // namespace network_port_state

using NetworkPortState =
    std::variant<network_port_state::Closed, network_port_state::Opening,
                 network_port_state::Reconnecting, network_port_state::Open,
                 network_port_state::Stopped>;

enum class NetworkPortEvent {
  open_asked,       // open()
  lost,             // lose(): the connection failed under the line
  attempt_failed,   // a connect attempt (and over RFC 2217 its negotiation) failed
  connected,        // a connect attempt succeeded
  stop_asked,       // stop()
  deadline_armed,   // a connect step starts under connect_timeout
  deadline_passed,  // connect_timeout passed before the step ended
};

// The state `event` moves a port in `state` to; none: the event cannot happen there.
std::optional<NetworkPortState> next_state(const NetworkPortState& state, NetworkPortEvent event);

// One port's state, moved only by next_state().
class NetworkPortStates {
 public:
  const NetworkPortState& state() const { return state_; }
  bool is_open() const { return std::holds_alternative<network_port_state::Open>(state_); }
  bool opening() const { return std::holds_alternative<network_port_state::Opening>(state_); }
  bool reconnecting() const {
    return std::holds_alternative<network_port_state::Reconnecting>(state_);
  }
  bool stopped() const { return std::holds_alternative<network_port_state::Stopped>(state_); }
  // Whether the connect step under way has passed connect_timeout; false when none is.
  bool deadline_passed() const;
  // Moves on `event`; false, and no move, when the event cannot happen in this state.
  bool on(NetworkPortEvent event);

 private:
  NetworkPortState state_ = network_port_state::Closed{};
};

}  // namespace tiltgate
