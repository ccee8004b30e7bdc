// The Modbus RTU family's descriptor (driver/family.h): any Modbus RTU slave, described by a
// device profile ([[sensor]] device = "FILE").
#pragma once

#include "driver/family.h"

namespace tiltgate::modbus_rtu {

extern const FamilyDescriptor kFamily;

}  // namespace tiltgate::modbus_rtu
