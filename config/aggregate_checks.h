// Checks of [[aggregate]] against the rest of the file, once the sensors' maps are loaded:
// the sensors or bus it names exist (and `bus` is resolved into its sensors, in file order);
// its sensors share one listener ([[bus]] tcp_port); its unit id is no sensor's, pass-through
// unit id's or earlier aggregate's on that listener; and its points exist with the same type
// and width in every sensor's map (mapping/aggregate_layout.h).
#pragma once

#include <vector>

#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

// `check_points`: false when the maps themselves had errors (the points are not checked).
void check_aggregates(std::vector<ParsedAggregate>& aggregates,
                      const std::vector<ParsedSensor>& sensors,
                      const std::vector<ParsedBus>& buses, bool check_points, ErrorList& errors,
                      FamilyList families);

}  // namespace tiltgate::config
