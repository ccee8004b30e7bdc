// The interface between the gateway core and a vendor's sensors. The core schedules; a driver
// turns "poll now" and "write this setting" into protocol transactions on a Line and keeps the
// SensorState the register map reads. Only drivers know a vendor.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "driver/expected.h"
#include "driver/line.h"
#include "driver/sensor_state.h"

namespace tiltgate {

// Settings a Modbus client can change. Each driver accepts the ones its sensors have.
enum class WriteTarget : std::uint8_t {
  filter,          // filter response / damping code
  zero_x,          // zero offset, axis 1 (degrees)
  zero_y,          // zero offset, axis 2 (degrees)
  command,         // one-shot commands; codes below
  baud_code,       // sensor baud code (takes effect after restart)
  bus_address,     // the sensor's bus address; the driver follows the sensor to it
  eeprom_location, // EEPROM window: which location the next value write goes to
  eeprom_value,    // EEPROM window: value written to the selected location
  sensor_offset,   // named EEPROM settings (Dyna)
  temperature_offset,
  pwm_offset,
};

// Values of WriteTarget::command.
enum class SensorCommand : std::uint16_t {
  zero_temporary = 1,  // zero to current angle, lost on restart
  zero_permanent = 2,  // zero to current angle, kept
  restart = 3,
};

enum class WriteErrorKind {
  not_supported,   // the sensor has no such setting (Modbus 0x02/0x01)
  bad_value,       // rejected before anything was sent (Modbus 0x03)
  rejected,        // the sensor refused the data (Rieker NAK 3; Modbus 0x03)
  refused,         // the sensor refused for another reason (other NAKs; Modbus 0x04)
  busy,            // still busy after the retries (Modbus 0x06)
  no_response,     // time-out or port failure (Modbus 0x0B)
};

struct WriteError {
  WriteErrorKind kind;
  std::string detail;  // for the log: which step failed and why
};

using WriteResult = Expected<Done, WriteError>;

class SensorDriver {
 public:
  virtual ~SensorDriver() = default;

  // "h6", "h4360", "dyna": selects the default register map.
  virtual std::string_view model() const = 0;

  // Whether a value may be written, checked before the write is queued.
  virtual WriteResult check_write(WriteTarget target, double value) const = 0;

  // The bus address this write would move the sensor to, if it moves it. The bus refuses one
  // that another of its sensors has, before the write is queued and again when it starts (an
  // earlier write may have moved a sensor, or selected the address for an EEPROM write).
  virtual std::optional<std::uint32_t> address_after(WriteTarget target, double value) const {
    if (target != WriteTarget::bus_address || !(value >= 0 && value <= 0xFFFF'FFFF)) return {};
    return std::uint32_t(value);
  }

  // One poll cycle: reads identity first when it is unknown (after start and after the line
  // reopened), then one measurement. Updates state(); never throws.
  virtual boost::asio::awaitable<void> poll(Line& line) = 0;

  // Carry out one write, including any unlocking the protocol needs. Answers only once the
  // sensor has acknowledged (or failed).
  virtual boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target,
                                                    double value) = 0;

  virtual const SensorState& state() const = 0;
};

}  // namespace tiltgate
