// `tiltgate capture`: what a line carries, as a pcapng file for Wireshark (docs/diagnostics.md,
// "Capture for Wireshark"). Two ways in:
//   --bus NAME [--config FILE | --control-socket PATH] --seconds N | --last
//       through the running gateway that polls the bus: its frames from now on, or its black
//       box (the last minute); the gateway's control socket is found as the commissioning
//       commands find it (--via-gateway).
//   --port TTY --protocol P --baud B
//       listen only, on a line another master drives: nothing is ever transmitted.
// --output FILE, or - for stdout: `tiltgate capture ... --output - | wireshark -k -i -`.
// Exit codes: 0 done (or stopped with Ctrl-C), 1 the gateway or the tty cannot be used, 2 a
// usage error.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"

namespace tiltgate {

Subcommand add_capture(CLI::App& app, FamilyList families);

}  // namespace tiltgate
