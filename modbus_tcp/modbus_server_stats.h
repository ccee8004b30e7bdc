// What a Modbus TCP server counts (the status page and /metrics read it): ModbusServerStats as
// read, and the atomic counters behind it, which the connections bump from their own threads.
#pragma once

#include <atomic>
#include <cstdint>

namespace tiltgate {

struct ModbusServerStats {
  std::uint64_t accepted = 0;          // connections served
  std::uint64_t refused = 0;           // connections closed at once: a limit reached, none idle
  std::uint64_t replaced = 0;          // idle connections closed to make room for a new one
  std::uint64_t denied = 0;            // connections closed at once: address not in allow
  std::uint64_t writes_denied = 0;     // writes answered 0x01: address not in write_allow, or a
                                       // TLS client's role read-only
  std::uint64_t tls_refused = 0;       // TLS handshakes failed: no client certificate, one not
                                       // signed by the CA, or not TLS 1.2+
  std::uint64_t requests = 0;          // checked requests passed to the handler
  std::uint64_t forwarded = 0;         // requests for units passed through to a device
  std::uint64_t rejected = 0;          // malformed or unsupported: answered by the parser
  std::uint64_t framing_errors = 0;    // connections closed for a bad MBAP header
  std::uint64_t request_timeouts = 0;  // connections closed with a request or reply stuck
  std::uint64_t idle_timeouts = 0;     // connections closed for silence
  std::uint64_t requests_delayed = 0;  // requests that waited for their turn under the rates
  std::uint64_t delay_ns = 0;          // the time they waited, together
};

// ModbusServerStats, counted from any thread.
struct ModbusServerCounters {
  std::atomic<std::uint64_t> accepted{0}, refused{0}, replaced{0}, denied{0}, writes_denied{0},
      tls_refused{0}, requests{0}, forwarded{0}, rejected{0}, framing_errors{0},
      request_timeouts{0}, idle_timeouts{0}, requests_delayed{0}, delay_ns{0};

  ModbusServerStats snapshot() const;
};

}  // namespace tiltgate
