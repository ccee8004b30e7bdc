// The subcommands that run simulated sensors: `demo` serves the families' demo sensors through
// a whole gateway, `sim FAMILY` runs one family's simulated bus on a pseudo-terminal.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family_commands.h"

namespace tiltgate {

// The demo serves each family of `commands` that has demo sensors.
Subcommand add_demo(CLI::App& app, FamilyCommandsList commands);
// One `sim` subcommand per family of `commands`; until SIGINT/SIGTERM.
Subcommand add_sim(CLI::App& app, FamilyCommandsList commands);

}  // namespace tiltgate
