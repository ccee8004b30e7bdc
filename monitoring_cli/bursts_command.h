// `tiltgate bursts`: a sensor's burst records (docs/monitoring.md, "Bursts"), read from the
// files in the configuration's [server] state_dir, beside a running gateway or after it stopped.
//   tiltgate bursts --config FILE --sensor NAME                  the list, newest first
//   tiltgate bursts --config FILE --sensor NAME --id ID|last [--output FILE]   one as CSV
// Exit codes: 0 done, 1 the file or the burst cannot be read (none with that id), 2 a usage
// error.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"

namespace tiltgate {

Subcommand add_bursts(CLI::App& app, FamilyList families);

}  // namespace tiltgate
