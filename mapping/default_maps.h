// The built-in register maps, one per sensor model: what a PLC sees with no map file.
#pragma once

#include <string_view>

#include "mapping/register_map.h"

namespace tiltgate {

// Empty map for an unknown model.
RegisterMap default_map(std::string_view model);

}  // namespace tiltgate
