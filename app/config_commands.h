// The subcommands that work on a configuration file: `run` serves it, `check` validates it,
// `map` prints its register maps (docs/configuration.md, docs/register-maps.md).
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"
#include "driver/family.h"

namespace tiltgate {

Subcommand add_run(CLI::App& app, FamilyList families);
Subcommand add_check(CLI::App& app, FamilyList families);
Subcommand add_map(CLI::App& app, FamilyList families);

}  // namespace tiltgate
