// `tiltgate baseline`: a sensor's baseline through the running gateway (docs/monitoring.md,
// "Baseline and displacement"): shown, taken from its current reading, set to a value, or
// cleared back to the configuration's. The gateway's control socket is found from --config as
// `tiltgate capture` finds it; the sensor's bus, which the session asks for, from the same file.
//   tiltgate baseline --config FILE --sensor NAME [--current | --x X [--y Y] | --clear]
// Without a change it shows the baseline in force. Exit codes: 0 done, 1 the gateway refused
// or cannot be reached, 2 a usage error.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"

namespace tiltgate {

Subcommand add_baseline(CLI::App& app, FamilyList families);

}  // namespace tiltgate
