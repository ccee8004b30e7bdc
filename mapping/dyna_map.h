// The built-in register map of the Spectron SPECTROTILT Dyna (single axis).
#pragma once

#include "mapping/register_map.h"

namespace tiltgate {

// Input registers 0..5: the angle (float32 and hundredths, where the Rieker maps have X) with
// the raw counts and raw temperature in the places a Rieker map gives to Y; 6..27 and the
// discrete inputs: the status block of every model, at the same addresses. Holding registers:
// the three EEPROM offsets, an EEPROM window (location, value), and command, baud code and
// module address at the Rieker map's addresses of the same settings.
RegisterMap dyna_default_map();

}  // namespace tiltgate
