#include "modbus_tcp/connection_stage.h"

namespace tiltgate {

std::optional<ConnectionStage> next_stage(ConnectionStage stage, ConnectionEvent event) {
  using S = ConnectionStage;
  using E = ConnectionEvent;
  if (event == E::closed) {
    if (stage == S::ended) return std::nullopt;  // it ends once
    return S::ended;
  }
  switch (stage) {
    case S::accepted:
      if (event == E::watched_plain) return S::serving;
      if (event == E::watched_tls) return S::handshaking;
      break;
    case S::handshaking:
      if (event == E::handshake_done) return S::serving;
      break;
    case S::serving:
      if (event == E::handed_over) return S::with_handler;
      break;
    case S::with_handler:
      if (event == E::handler_done) return S::serving;
      break;
    case S::ended: break;
  }
  return std::nullopt;
}

bool ConnectionStages::on(ConnectionEvent event) {
  const std::optional<ConnectionStage> next = next_stage(stage_, event);
  if (!next) return false;
  stage_ = *next;
  return true;
}

}  // namespace tiltgate
