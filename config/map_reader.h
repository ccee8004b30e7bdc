// Reading a register map: a map file's top level, or a [[sensor]]'s inline `map` table, which
// have the same keys (extends, remove, [[point]]). Then checking it as one sensor's map and
// reporting every problem at the line of the key it is about.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <string_view>
#include <vector>

#include "config/error_list.h"
#include "mapping/map_definition.h"

namespace tiltgate::config {

struct ParsedMap {
  MapDefinition definition;
  Located where;                // extends, remove, point
  std::vector<Located> points;  // where each point's keys are, as definition.points
  bool complete = true;         // read without errors, so worth checking as a whole
};

// `path` names the table in messages: "" for a map file's top level, "sensor[0].map" inline.
ParsedMap read_map(const toml::table& table, std::string path, ErrorList& errors);

// Checks `map` as the map of a sensor of `model` (mapping/map_validation.h); a map that is not
// `complete` is not checked further (its points hold defaults where keys were wrong).
void check_map(const ParsedMap& map, std::string_view model, ErrorList& errors);

}  // namespace tiltgate::config
