// The built-in register map of the Spectron SPECTROTILT Dyna (single axis).
#pragma once

#include "mapping/register_map.h"

namespace tiltgate::spectron {

// The common block of every model (mapping/common_block.h): the angle as X, Y not available,
// filter and zero offsets not available, command 1 = reset, baud code and module address as
// EEPROM 22 and 16. From input register 100 the raw counts and raw temperature; from holding
// register 100 the three EEPROM offsets and the EEPROM window (location, value).
RegisterMap dyna_default_map();

}  // namespace tiltgate::spectron
