// The Dyna's settings as EEPROM locations ("Memory Map", spectron/eeprom_map.h), shared by the
// driver's writes and its read-back.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "driver/write_target.h"
#include "spectron/setting_ids.h"
#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {

// The settings that are one EEPROM word each, read back with the identity.
inline constexpr std::array<WriteTarget, 5> kEepromSettings{
    setting::sensor_offset, setting::temperature_offset, setting::pwm_offset,
    WriteTarget::baud_code, WriteTarget::bus_address};

// The EEPROM location behind a named setting; none for the window and the command.
constexpr std::optional<std::uint16_t> location_of(WriteTarget target) {
  switch (target) {
    case setting::sensor_offset: return eeprom::kSensorOffset;
    case setting::temperature_offset: return eeprom::kTemperatureOffset;
    case setting::pwm_offset: return eeprom::kPwmOffset;
    case WriteTarget::bus_address: return eeprom::kModuleAddress;
    case WriteTarget::baud_code: return eeprom::kBaudCode;
    default: return std::nullopt;
  }
}

}  // namespace tiltgate::spectron
