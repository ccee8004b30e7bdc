// The command-line side of the commissioning commands: the bus and sensor options they share
// (commission/commission_options.h) and their help.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "commission/commission_options.h"
#include "driver/family_commands.h"

namespace tiltgate {

// One subcommand of the executable, as its add_<command>() function left it on the command
// line: CLI11 records in `cli` whether it was chosen, and `run` carries it out with the options
// parsed into it, returning the process's exit code.
struct Subcommand {
  CLI::App* cli = nullptr;
  std::function<int()> run;
  // Warnings off unless --log-level asks for them: a commissioning command's own output is the
  // point, and the drivers' warnings about a silent sensor would only repeat it (and break the
  // redrawn table).
  bool quiet = false;
};

// --port, --protocol, --baud, --parity, --stop-bits, --master-address, --model, --device,
// --config, --sensor, --bus and --address, filling `options`; the protocols are `families'`.
// With `auto_baud`, --baud also takes "auto", which sets it.
void add_bus_options(CLI::App& command, BusOptions& options, FamilyList families,
                     bool* auto_baud = nullptr);

// The commands' --help footers: examples for each family's demo bus, and the exit status.
std::string info_help_footer(FamilyCommandsList families);
std::string watch_help_footer(FamilyCommandsList families);
std::string scan_help_footer(FamilyCommandsList families);
std::string set_help_footer(FamilyCommandsList families);
std::string raw_help_footer(FamilyCommandsList families);

}  // namespace tiltgate
