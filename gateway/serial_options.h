// A [[bus]] as the serial transport needs it: timing from the bus, framing from its protocol's
// descriptor (driver/family.h).
#pragma once

#include "config/config.h"
#include "driver/family.h"
#include "serial/serial_line.h"

namespace tiltgate {

SerialLineOptions serial_options_from(const BusConfig& bus,
                                      FamilyList families = registered_families());

}  // namespace tiltgate
