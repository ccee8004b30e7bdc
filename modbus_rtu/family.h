// The Modbus RTU family's descriptor (driver/family.h): any Modbus RTU slave, described by a
// device profile. Not in families/family_list.cpp yet: its driver and the [[sensor]] device
// key come next, and until then the descriptor is only used by the tests.
#pragma once

#include "driver/family.h"

namespace tiltgate::modbus_rtu {

extern const FamilyDescriptor kFamily;

}  // namespace tiltgate::modbus_rtu
