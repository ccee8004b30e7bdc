// Who may change a setting (issue 42's roles): a shift operator may change the harmless
// measurement settings (zero, filter); everything that can lose the sensor (its address, baud,
// restart, factory reset, lock level, EEPROM writes) needs an admin. A family marks its
// settings (SettingDescriptor), a device profile its writable values, a map file its writable
// points (`role`); unmarked means admin.
#pragma once

#include <cstdint>

namespace tiltgate {

enum class SettingRole : std::uint8_t { operator_, admin };

}  // namespace tiltgate
