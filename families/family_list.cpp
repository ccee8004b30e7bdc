// The one list of sensor families this build serves. A new family is its folder plus one line
// here (README, "Adding a sensor family").
#include "driver/family.h"
#include "modbus_rtu/family.h"
#include "rieker/family.h"
#include "spectron/family.h"

namespace tiltgate {

namespace {

const FamilyDescriptor* const kFamilies[] = {
    &rieker::kFamily,
    &spectron::kFamily,
    &modbus_rtu::kFamily,
};

}  // namespace

FamilyList registered_families() { return kFamilies; }

}  // namespace tiltgate
