// One plain-language hint for a bus whose failures make a clear pattern, for the technician
// reading the console's bus page or /api/buses ("hint"): where to look first. From the last
// kRecentFailuresWindow's failures of its sensors (their counts since start until those are
// counted). None when the pattern is not clear. docs/diagnostics.md, "Reading the counts".
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gateway/gateway_status.h"

namespace tiltgate {

// In order, the first that holds:
// - checksum errors on every sensor of a bus of two or more: its rate, termination or bias;
// - checksum errors on one sensor only: its drop cable, or a second device at its address;
// - time-outs on every sensor of a bus behind a serial device server that has reconnected: the
//   server's packing delay;
// - time-outs on one sensor only, its neighbours answering: that sensor's power, address or drop.
std::optional<std::string> line_hint(const BusStatus& bus, const std::vector<SensorStatus>& sensors);

}  // namespace tiltgate
