// The Rieker Flex family (H6, H4360): the descriptor the gateway runs and the one the command
// line shows.
#pragma once

#include "driver/family.h"
#include "driver/family_commands.h"

namespace tiltgate::rieker {

extern const FamilyDescriptor kFamily;
extern const FamilyCommands kCommands;

}  // namespace tiltgate::rieker
