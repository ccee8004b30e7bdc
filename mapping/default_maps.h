// The built-in register maps, one per sensor model: what a PLC sees with no map file.
#pragma once

#include <string_view>
#include <vector>

#include "driver/family.h"
#include "mapping/register_map.h"

namespace tiltgate {

// The built-in map of `model`, one of `families`' models; an empty map for an unknown model.
RegisterMap default_map(FamilyList families, std::string_view model);
// The models that have a built-in map: what a map file may extend.
std::vector<std::string_view> models_with_default_maps(FamilyList families);

}  // namespace tiltgate
