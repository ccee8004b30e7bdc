// The stages of one Modbus TCP connection on its loop (modbus_tcp/modbus_tcp_connection.h) and
// the only moves between them, in one place: a stage is one value, so a connection cannot be
// ended and with its handler at once, or serve requests before its TLS handshake is done.
// Pure: no socket, no loop.
#pragma once

#include <optional>

namespace tiltgate {

enum class ConnectionStage {
  accepted,      // not yet watched by its loop
  handshaking,   // TLS: watched, its handshake under way
  serving,       // reading requests, answering them and sending the replies
  with_handler,  // a request is with the handler: nothing else is answered until its reply
  ended,         // its socket closed: nothing more happens
};

enum class ConnectionEvent {
  watched_plain,   // its loop watches it, a plain TCP stream
  watched_tls,     // its loop watches it, a TLS stream: the handshake begins
  handshake_done,  // the TLS handshake succeeded
  handed_over,     // a request went to the handler
  handler_done,    // the handler's reply came back, or handler_timeout answered 0x0B instead
  closed,          // it ends, for whatever reason
};

// The stage `event` moves a connection in `stage` to; none: the event cannot happen there.
std::optional<ConnectionStage> next_stage(ConnectionStage stage, ConnectionEvent event);

// Whether its loop watches the socket in `stage` (so ending it stops the watch).
constexpr bool is_watched(ConnectionStage stage) {
  return stage != ConnectionStage::accepted && stage != ConnectionStage::ended;
}

// One connection's stage, moved only by next_stage().
class ConnectionStages {
 public:
  ConnectionStage stage() const { return stage_; }
  bool is(ConnectionStage stage) const { return stage_ == stage; }
  // Moves on `event`; false, and no move, when the event cannot happen in this stage.
  bool on(ConnectionEvent event);

 private:
  ConnectionStage stage_ = ConnectionStage::accepted;
};

}  // namespace tiltgate
