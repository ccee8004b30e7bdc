// The Rieker Flex family (H6, H4360) as the core sees it: one descriptor.
#pragma once

#include "driver/family.h"

namespace tiltgate::rieker {

extern const FamilyDescriptor kFamily;

}  // namespace tiltgate::rieker
