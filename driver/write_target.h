// The settings a Modbus client can change, and what the gateway knows of their values.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace tiltgate {

// Settings a Modbus client can change. Each driver accepts the ones its sensors have.
enum class WriteTarget : std::uint8_t {
  filter,          // filter response / damping code
  zero_x,          // zero offset, axis 1 (degrees)
  zero_y,          // zero offset, axis 2 (degrees)
  command,         // one-shot commands; codes in driver/sensor_driver.h
  baud_code,       // sensor baud code (takes effect after restart)
  bus_address,     // the sensor's bus address; the driver follows the sensor to it
  eeprom_location, // EEPROM window: which location the next value write goes to
  eeprom_value,    // EEPROM window: value written to the selected location
  sensor_offset,   // named EEPROM settings
  temperature_offset,
  pwm_offset,
};
inline constexpr std::size_t kWriteTargetCount = std::size_t(WriteTarget::pwm_offset) + 1;

// The value of each setting as the sensor holds it: read back from the sensor where its
// protocol can, else the value it acknowledged for a write through the gateway. Empty while
// not known (no read-back yet, nothing written, or a setting the sensor does not have).
class KnownSettings {
 public:
  std::optional<double> get(WriteTarget target) const { return values_[index(target)]; }
  void set(WriteTarget target, double value) { values_[index(target)] = value; }
  void forget(WriteTarget target) { values_[index(target)].reset(); }

 private:
  static std::size_t index(WriteTarget target) { return std::size_t(target); }
  std::array<std::optional<double>, kWriteTargetCount> values_{};
};

}  // namespace tiltgate
