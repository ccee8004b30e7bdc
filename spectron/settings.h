// The settings the Dyna accepts, with their ranges: EEPROM words ("Memory Map",
// spectron/eeprom_map.h) are raw 16-bit words; module addresses 0..255 on a 9-bit bus and
// 1..250 on Modbus-ASCII, baud codes 7, 10, 15, 32 and 64 only, and EEPROM locations the even
// 2..22 and 100..280 (the driver checks those exactly). The descriptor lists them
// (spectron/family.cpp) and the built-in map takes its holding registers from them
// (spectron/default_map.cpp).
// Every one of them needs an admin: each is a write of the module's EEPROM (wear, and its
// address and baud can lose the module), the EEPROM window writes any location, and the
// command resets the module. The Dyna has no filter, and its zero is the gateway's
// zero_counts, a configuration key.
#pragma once

#include "driver/family.h"
#include "spectron/setting_ids.h"

namespace tiltgate::spectron::settings {

using T = SettingType;

inline constexpr CommandAction kCommandActions[] = {
    {1, "Reset the module",
     "Reset {sensor}? The module does not answer until it has started again."},
};
inline constexpr SettingDescriptor command =
    common_setting::command.accepting(T::integer, 1, 1, "", "1 resets the module")
        .doing(kCommandActions);
// The EEPROM words are read back from the module (DynaDriver::read_settings); the window's
// location is the gateway's own choice, and the command is no setting to read.
inline constexpr SettingDescriptor baud_code =
    common_setting::baud_code
        .accepting(T::integer, 7, 64, "",
                   "EEPROM 22: 7 38400, 10 28800, 15 19200, 32 9600, 64 4800; takes effect "
                   "after a reset")
        .read_from_sensor();
inline constexpr SettingDescriptor bus_address =
    common_setting::bus_address
        .accepting(T::integer, 0, 255, "", "EEPROM 16, module address; the gateway follows the module")
        .read_from_sensor();

inline constexpr SettingDescriptor sensor_offset =
    SettingDescriptor{"sensor_offset", setting::sensor_offset, T::integer, 0, 65535, "",
                      "EEPROM 6, offset for the sensor (subtracted by the module)"}
        .labelled("Sensor offset")
        .read_from_sensor();
inline constexpr SettingDescriptor temperature_offset =
    SettingDescriptor{"temperature_offset", setting::temperature_offset, T::integer, 0, 65535,
                      "", "EEPROM 10, offset for the temperature sensor"}
        .labelled("Temperature offset")
        .read_from_sensor();
inline constexpr SettingDescriptor pwm_offset =
    SettingDescriptor{"pwm_offset", setting::pwm_offset, T::integer, 0, 65535, "",
                      "EEPROM 20, offset for the PWM output"}
        .labelled("PWM offset")
        .read_from_sensor();
inline constexpr SettingDescriptor eeprom_location =
    SettingDescriptor{"eeprom_location", setting::eeprom_location, T::integer, 2, 280, "",
                      "EEPROM window: selects a location and reads it from the module"}
        .labelled("EEPROM window, location");
inline constexpr SettingDescriptor eeprom_value =
    SettingDescriptor{"eeprom_value", setting::eeprom_value, T::integer, 0, 65535, "",
                      "EEPROM window: the selected location as read back; a write writes it"}
        .labelled("EEPROM window, value")
        .read_from_sensor();

}  // namespace tiltgate::spectron::settings
