// Checks across tables: names and unit ids that must be unique, two buses on one tty, and
// each sensor against its bus (protocol, address range, address clashes).
#pragma once

#include <vector>

#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

void check_buses(const std::vector<ParsedBus>& buses, ErrorList& errors);
void check_sensors(const std::vector<ParsedSensor>& sensors, const std::vector<ParsedBus>& buses,
                   ErrorList& errors, FamilyList families);

}  // namespace tiltgate::config
