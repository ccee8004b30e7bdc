// Checks of [[bus]] pass_through against the rest of the file: a unit id is passed through on
// one bus at most, is never also a [[sensor]]'s unit_id, and a passed-through device's
// address is no sensor's address on the same bus (both would answer).
#pragma once

#include <vector>

#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

void check_pass_through(const std::vector<ParsedBus>& buses,
                        const std::vector<ParsedSensor>& sensors, ErrorList& errors);

}  // namespace tiltgate::config
