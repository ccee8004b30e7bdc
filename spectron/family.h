// The Spectron SPECTROTILT Dyna family (both protocols): the descriptor the gateway runs and
// the one the command line shows.
#pragma once

#include "driver/family.h"
#include "driver/family_commands.h"

namespace tiltgate::spectron {

extern const FamilyDescriptor kFamily;
extern const FamilyCommands kCommands;

}  // namespace tiltgate::spectron
