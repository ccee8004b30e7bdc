#include "modbus_tcp/modbus_server_stats.h"

namespace tiltgate {

ModbusServerStats ModbusServerCounters::snapshot() const {
  // Designated, so the compiler holds each count to its field of the same name.
  return {.accepted = accepted, .refused = refused, .replaced = replaced, .denied = denied,
          .writes_denied = writes_denied, .tls_refused = tls_refused, .requests = requests,
          .forwarded = forwarded, .rejected = rejected, .framing_errors = framing_errors,
          .request_timeouts = request_timeouts, .idle_timeouts = idle_timeouts,
          .requests_delayed = requests_delayed, .delay_ns = delay_ns};
}

}  // namespace tiltgate
