// What a bus answers those who wait on it besides writes (driver/sensor_driver.h WriteResult):
// a request forwarded to a device it passes through ([[bus]] pass_through), and one
// transaction of a commissioning command through the control socket.
#pragma once

#include <cstdint>
#include <vector>

#include "driver/expected.h"
#include "driver/line.h"

namespace tiltgate {

// Why a forwarded request got no reply PDU to relay.
enum class ForwardFailure {
  busy,         // the bus's forward queue was full (Modbus 0x06)
  expired,      // still queued at its deadline (0x0B)
  no_response,  // sent, but no reply: time-out, port closed or failed; or stopping (0x0B)
  unframed,     // the bus's protocol cannot frame it, or cannot forward at all (0x04)
  standby,      // the gateway is the standby of a redundant pair: it sends nothing (0x0A)
};
const char* to_string(ForwardFailure failure);

// The reply PDU (function code and data, exception replies included) or why there is none.
using ForwardResult = Expected<std::vector<std::uint8_t>, ForwardFailure>;

// What a commissioning command's transaction through the control socket came to: the Line's
// outcome, its timing and generation, as the command's own Line would report them.
struct CommandExchangeResult {
  Expected<Done, LineError> done = Done{};
  bool expired = false;  // never sent: still queued at its deadline
  LineTiming timing;
  std::uint64_t generation = 0;
};

}  // namespace tiltgate
