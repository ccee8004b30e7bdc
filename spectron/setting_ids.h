// The Dyna's own settings (beyond the common block's), as ids the family owns
// (driver/write_target.h) and names in its descriptor (spectron/family.cpp).
#pragma once

#include "driver/write_target.h"

namespace tiltgate::spectron::setting {

inline constexpr WriteTarget eeprom_location{kFirstFamilySetting + 0};  // EEPROM window: which
                                                                        // location is selected
inline constexpr WriteTarget eeprom_value{kFirstFamilySetting + 1};  // the selected location
inline constexpr WriteTarget sensor_offset{kFirstFamilySetting + 2};  // EEPROM 6
inline constexpr WriteTarget temperature_offset{kFirstFamilySetting + 3};  // EEPROM 10
inline constexpr WriteTarget pwm_offset{kFirstFamilySetting + 4};  // EEPROM 20

}  // namespace tiltgate::spectron::setting
