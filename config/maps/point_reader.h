// Reading one [[point]] of a register map (a map file, or a [[sensor]]'s inline map) into a
// mapping Point. Only the keys are checked here (types, names, ranges of single keys); whether
// the points make a consistent map for a sensor is mapping/map_validation.h's business.
#pragma once

#include <toml++/toml.h>

#include <string>

#include "toml/error_list.h"
#include "mapping/point.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::Located;

struct ParsedPoint {
  Point point;
  Located where;
};

// Settings are written by the names `families` give them.
ParsedPoint read_point(const toml::table& table, std::string path, ErrorList& errors,
                       FamilyList families);

}  // namespace tiltgate::config
