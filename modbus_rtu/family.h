// The Modbus RTU family's descriptors (driver/family.h, driver/family_commands.h): any Modbus
// RTU slave, described by a device profile ([[sensor]] device = "FILE").
#pragma once

#include "driver/family.h"
#include "driver/family_commands.h"

namespace tiltgate::modbus_rtu {

extern const FamilyDescriptor kFamily;
extern const FamilyCommands kCommands;

}  // namespace tiltgate::modbus_rtu
