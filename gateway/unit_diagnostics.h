// What a unit's Modbus 08 (Diagnostics) counts and 11 (Get Comm Event Counter) answer: the
// exchanges of its sensor as the gateway sees them on that device's line, from the sensor's
// counters (driver/sensor_state.h SensorCounters); an aggregate unit's are its sensors' summed.
// Each count is 16 bits and wraps, as the Modbus counters do. The manual's table:
// docs/diagnostics.md.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "driver/sensor_state.h"

namespace tiltgate {

// The count that 08's `sub_function` (0x000B..0x0012) returns:
//   0x000B bus messages: every frame of the device's exchanges seen on its line, the gateway's
//          requests and every reply heard (valid, garbled or late);
//   0x000C bus communication errors: replies that failed their checksum or made no frame;
//   0x000D exception errors: refusals (NAKs and exception replies);
//   0x000E server messages: requests sent to the device, retries included;
//   0x000F no response: requests that heard nothing at all in time;
//   0x0010 NAKs: refusals that were not busy;
//   0x0011 busy: refusals that said busy;
//   0x0012 character overruns: characters the gateway's port lost during the device's
//          replies (0 on ports that cannot count them).
// None for another sub-function.
std::optional<std::uint16_t> diagnostic_count(const SensorCounters& counters,
                                              std::uint16_t sub_function);

// 11's status word (0x0000: the gateway answers from its cache and is never busy with it) and
// event count (the device's valid replies).
struct CommEventCounter {
  std::uint16_t status = 0x0000;
  std::uint16_t events = 0;
};
CommEventCounter comm_event_counter(const SensorCounters& counters);

// The counters of several sensors as one (an aggregate unit's): each count summed.
void add_counts(SensorCounters& total, const SensorCounters& counters);

}  // namespace tiltgate
