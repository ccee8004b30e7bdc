// Reading a register map: a map file's top level, or a [[sensor]]'s inline `map` table, which
// have the same keys (extends, remove, [[point]]). Then checking it as one sensor's map and
// reporting every problem at the line of the key it is about.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <span>
#include <string_view>
#include <vector>

#include "toml/error_list.h"
#include "driver/device_value.h"
#include "mapping/map_definition.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::Located;

struct ParsedMap {
  MapDefinition definition;
  Located where;                // extends, remove, point
  std::vector<Located> points;  // where each point's keys are, as definition.points
  std::vector<bool> points_read;  // as definition.points: the point read without errors
  bool header_read = true;        // extends, remove and the map's own keys read without errors
};

// `path` names the table in messages: "" for a map file's top level, "sensor[0].map" inline.
ParsedMap read_map(const toml::table& table, std::string path, ErrorList& errors,
                   FamilyList families);

// Checks `map` as the map of a sensor of `model` whose own values are `device_values`
// (mapping/map_validation.h); model "" when the sensor's model is itself in error. Only what read without errors is checked, so that a key
// error elsewhere hides no map problem in the same run and adds no false one: a point with a
// wrong key (it holds defaults) is left out, and so are the built-in points when `extends`,
// `remove` or the model could not be read.
void check_map(const ParsedMap& map, std::string_view model,
               std::span<const DeviceValue> device_values, ErrorList& errors,
               FamilyList families);

}  // namespace tiltgate::config
