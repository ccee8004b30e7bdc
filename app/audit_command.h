// `tiltgate audit`: prints the audit trail a gateway keeps in <state_dir>/audit/
// (docs/operations.md, "The audit trail"), read without opening it, so it works beside a running gateway and after
// it stopped: for an SSH user, and the tests' view of the trail after a restart.
#pragma once

#include <CLI/CLI.hpp>

#include "commission_cli/commission_cli.h"

namespace tiltgate {

Subcommand add_audit(CLI::App& app);

}  // namespace tiltgate
