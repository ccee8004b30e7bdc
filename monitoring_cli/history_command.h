// `tiltgate history`: a sensor's long record as CSV (docs/monitoring.md, "The long record"),
// read from the files in the configuration's [server] state_dir, beside a running gateway or
// after it stopped; any range, written a day at a time.
//   tiltgate history --config FILE --sensor NAME [--from T] [--to T] [--output FILE]
// T: Unix milliseconds or UTC ISO 8601 (2026-12-07T10:00Z), as the HTTP download takes them.
// Exit codes: 0 done, 1 the file or the record cannot be read, 2 a usage error.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"

namespace tiltgate {

Subcommand add_history(CLI::App& app, FamilyList families);

}  // namespace tiltgate
