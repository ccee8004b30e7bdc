// The commissioning subcommands of the tiltgate executable (docs/commissioning.md): each adds
// itself, its options and its help to the command line. Exit codes: 0 on success, 1 when a
// sensor does not answer or the tty cannot be used, 2 on a usage error.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"
#include "driver/family_commands.h"

namespace tiltgate {

// `tiltgate info`: each sensor's identity, lock level and angles.
Subcommand add_info(CLI::App& app, FamilyList families, FamilyCommandsList commands);
// `tiltgate watch`: every sensor polled in turn, one row each, until stopped or --count rounds.
Subcommand add_watch(CLI::App& app, FamilyList families, FamilyCommandsList commands);
// `tiltgate scan`: every address of a range probed, one row per sensor that answered.
Subcommand add_scan(CLI::App& app, FamilyList families, FamilyCommandsList commands);
// `tiltgate set`: one setting of one sensor, then its state read back; `commands` holds the
// families' set helpers.
Subcommand add_set(CLI::App& app, FamilyList families, FamilyCommandsList commands);
// `tiltgate raw`: one request by function number, the bytes each way and the reply decoded;
// `commands` holds the families' raw request builders.
Subcommand add_raw(CLI::App& app, FamilyList families, FamilyCommandsList commands);

}  // namespace tiltgate
