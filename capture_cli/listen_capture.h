// `tiltgate capture --port TTY --protocol P --baud B`: listen only on a line another master
// drives (capture/line_listener.h), each frame handed on as it is decoded.
// (Interface fixed by capture_command.cpp; the implementation is listen_capture.cpp.)
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "driver/captured_frame.h"
#include "driver/family.h"

namespace tiltgate {

struct ListenCaptureOptions {
  std::string port;                              // the tty
  const ProtocolDescriptor* protocol = nullptr;  // never null
  std::uint32_t baud = 0;
  std::string parity;  // "even", "odd", "none"; empty: the protocol's
  int stop_bits = 0;   // 1 or 2; 0: the protocol's
  std::chrono::seconds duration{0};  // 0: until SIGINT or SIGTERM
};

// Runs its own event loop until `duration` passed, a signal, or `on_frame` returns false (the
// output cannot be written any more). Prints a one-line summary on stderr. 0 when done, 1 when
// the tty cannot be used (said on stderr), 2 for options the protocol refuses.
int run_listen_capture(const ListenCaptureOptions& options,
                       std::function<bool(const CapturedFrame&)> on_frame);

}  // namespace tiltgate
