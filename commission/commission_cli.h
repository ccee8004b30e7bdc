// The command-line side of the commissioning commands: the bus and sensor options they share
// (commission/commission_options.h) and their help.
#pragma once

#include <CLI/CLI.hpp>

#include "commission/commission_options.h"
#include "driver/family_commands.h"

namespace tiltgate {

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
