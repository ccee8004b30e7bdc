// A [[bus]] as the serial transport needs it: timing from the bus, framing from its protocol's
// descriptor (driver/family.h).
#pragma once

#include "config/config.h"
#include "driver/family.h"
#include "serial/serial_line.h"

namespace tiltgate {

// The framing is the bus's protocol's, one of `families`' protocols.
SerialLineOptions serial_options_from(FamilyList families, const BusConfig& bus);

}  // namespace tiltgate
