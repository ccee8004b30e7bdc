// The built-in register maps of the Rieker Flex models: the common block only.
#pragma once

#include "mapping/register_map.h"

namespace tiltgate::rieker {

RegisterMap h6_default_map();
RegisterMap h4360_default_map();

}  // namespace tiltgate::rieker
