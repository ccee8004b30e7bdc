// The settings the Rieker models accept, with their ranges from the manual: Set Filter Response
// (41) takes 1..6, Set Baud (38) codes 1..8, Set Address (2) 1..65000, and a zero offset beyond
// the +-180 deg measuring range makes no sense. The descriptor lists them (rieker/family.cpp)
// and the built-in maps take their holding registers from them (rieker/default_maps.cpp).
// A shift operator may change the filter and the zero offsets (measurement settings the sensor
// keeps answering through) and zero the sensor to its current angle (command 1 or 2); a
// restart (command 3), the baud and the address can lose the sensor and need an admin.
// The sensor answers no read of its settings (rieker/rieker_driver.cpp): none is read back, and
// what the gateway knows of each is what it last wrote.
#pragma once

#include "driver/family.h"

namespace tiltgate::rieker::settings {

using T = SettingType;

inline constexpr SettingDescriptor filter = common_setting::filter.accepting(
    T::integer, 1, 6, "", "Set Filter Response 1 (fast, noisy) .. 6 (slow, quiet)",
    SettingRole::operator_);
inline constexpr SettingDescriptor zero_x =
    common_setting::zero_x.accepting(T::real, -180, 180, "deg", "Set Zero To Value, axis 1",
                                     SettingRole::operator_);
inline constexpr SettingDescriptor zero_y =
    common_setting::zero_y.accepting(T::real, -180, 180, "deg", "Set Zero To Value, axis 2",
                                     SettingRole::operator_);
inline constexpr double kZeroCommands[] = {1, 2};
// What each command does, as the console's buttons and questions say it.
inline constexpr CommandAction kCommandActions[] = {
    {1, "Zero to the current angle (until restart)",
     "Zero {sensor} to its current angle? Until the sensor restarts."},
    {2, "Zero permanently",
     "Zero {sensor} to its current angle permanently? The sensor keeps this zero after a restart."},
    {3, "Restart the sensor",
     "Restart {sensor}? It does not answer until it has started again."},
};
inline constexpr SettingDescriptor command =
    common_setting::command
        .accepting(T::integer, 1, 3, "", "1 zero to current angle (temporary), 2 (permanent), 3 restart")
        .letting_operator_write(kZeroCommands)
        .doing(kCommandActions);
inline constexpr SettingDescriptor baud_code = common_setting::baud_code.accepting(
    T::integer, 1, 8, "", "Set Baud 1..8, takes effect after restart");
inline constexpr SettingDescriptor bus_address = common_setting::bus_address.accepting(
    T::integer, 1, 65000, "", "Set Address; the gateway follows the sensor");

}  // namespace tiltgate::rieker::settings
