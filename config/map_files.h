// The register maps of all sensors, once every [[sensor]] is read: map files are loaded (each
// once, relative to the configuration file's directory), and every map, from a file or
// inline, is checked as the map of its sensor's model. So `tiltgate check` reports map
// mistakes, and `run` never starts with a bad map.
#pragma once

#include <string_view>
#include <vector>

#include "config/config_loader.h"
#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

// Sets each sensor's config.map (and map_file). Problems in the configuration file (a map
// file that cannot be opened, an inline map) go to `errors`; the problems found in map files
// are returned, file by file in the order the sensors name them, each file's in line order.
ConfigErrors load_sensor_maps(std::vector<ParsedSensor>& sensors, std::string_view config_path,
                              ErrorList& errors, FamilyList families);

}  // namespace tiltgate::config
