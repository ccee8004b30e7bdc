// What a warm standby cannot do on a valid configuration's buses (docs/configuration.md,
// "[redundancy]"): not errors, since the pair runs, but a line the standby cannot hear, or
// hears less of, changes what its takeover means. `tiltgate check` prints them beside the
// line budget's warnings (line_scheduling/line_budget.h).
#pragma once

#include <string>
#include <vector>

#include "config/config.h"
#include "driver/family.h"

namespace tiltgate {

// One warning a bus, in the file's order, naming the bus; none without [redundancy].
std::vector<std::string> redundancy_warnings(const Config& config, FamilyList families);

}  // namespace tiltgate
