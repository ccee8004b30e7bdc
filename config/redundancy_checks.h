// [redundancy] against the buses, while the file is loaded: the standby takes the lines over
// when it has heard no request of the primary on any of them for takeover_ms, so takeover_ms
// must outlast the quiet a live primary leaves on each line it can hear (docs/configuration.md,
// "[redundancy]"). What a standby cannot do but the pair still runs with is not an error:
// config/redundancy_warnings.h.
#pragma once

#include <vector>

#include "config/sections.h"

namespace tiltgate::config {

// For every bus on a local serial line that has sensors: takeover_ms at least twice its
// shortest poll_ms, else an error at takeover_ms naming the bus, the sensor and both fixes.
void check_takeover(const ParsedRedundancy& redundancy, const std::vector<ParsedBus>& buses,
                    const std::vector<ParsedSensor>& sensors, ErrorList& errors);

}  // namespace tiltgate::config
