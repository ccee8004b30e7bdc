// `tiltgate user add|passwd|remove|list`: the web console's accounts in the users file
// (docs/web-console.md, "Accounts").
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"

namespace tiltgate {

Subcommand add_user(CLI::App& app);

}  // namespace tiltgate
