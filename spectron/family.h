// The Spectron SPECTROTILT Dyna family (both protocols) as the core sees it: one descriptor.
#pragma once

#include "driver/family.h"

namespace tiltgate::spectron {

extern const FamilyDescriptor kFamily;

}  // namespace tiltgate::spectron
