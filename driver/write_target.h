// The settings a Modbus client can change, and what the gateway knows of their values.
//
// A setting is a small id. The settings of the common register block (mapping/common_block.h)
// have the ids below, the same on every model; a sensor family numbers its own settings from
// kFirstFamilySetting and names them in its descriptor (SettingDescriptor, driver/family.h),
// which is where a map file's `write = "NAME"` finds them. A sensor's own writable values
// (driver/device_value.h) are ids from kFirstDeviceValue, by their index in its list.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace tiltgate {

struct WriteTarget {
  std::uint8_t id = 0;

  // The common block's settings.
  static const WriteTarget filter;       // filter response / damping code
  static const WriteTarget zero_x;       // zero offset, axis 1 (degrees)
  static const WriteTarget zero_y;       // zero offset, axis 2 (degrees)
  static const WriteTarget command;      // one-shot commands; codes in driver/sensor_driver.h
  static const WriteTarget baud_code;    // sensor baud code (takes effect after restart)
  static const WriteTarget bus_address;  // the sensor's bus address; the driver follows it

  // The sensor's own value `index` (DeviceValue, driver/device_value.h); index below
  // kMaxDeviceValues.
  static constexpr WriteTarget device_value(std::size_t index);
  constexpr bool is_device_value() const;
  constexpr std::size_t device_index() const;

  // An id, so that drivers can switch on settings.
  constexpr operator std::uint8_t() const { return id; }
};

inline constexpr WriteTarget WriteTarget::filter{0};
inline constexpr WriteTarget WriteTarget::zero_x{1};
inline constexpr WriteTarget WriteTarget::zero_y{2};
inline constexpr WriteTarget WriteTarget::command{3};
inline constexpr WriteTarget WriteTarget::baud_code{4};
inline constexpr WriteTarget WriteTarget::bus_address{5};

// The first id a family gives its own settings, and the number of those ids there are.
inline constexpr std::uint8_t kFirstFamilySetting = 16;
inline constexpr std::size_t kSettingIdCount = 32;

// A sensor's own values take the ids from here to 254; 255 is a map point's `write` naming a
// value no sensor was matched with yet (mapping/device_values.h resolves it).
inline constexpr std::uint8_t kFirstDeviceValue = 64;
inline constexpr std::size_t kMaxDeviceValues = 255 - kFirstDeviceValue;
inline constexpr WriteTarget kUnresolvedDeviceValue{255};

constexpr WriteTarget WriteTarget::device_value(std::size_t index) {
  return WriteTarget{std::uint8_t(kFirstDeviceValue + index)};
}
constexpr bool WriteTarget::is_device_value() const { return id >= kFirstDeviceValue; }
constexpr std::size_t WriteTarget::device_index() const { return id - kFirstDeviceValue; }

// The value of each setting as the sensor holds it: read back from the sensor where its
// protocol can, else the value it acknowledged for a write through the gateway. Empty while
// not known (no read-back yet, nothing written, or a setting the sensor does not have).
// A sensor's own values are not kept here: they are read with every poll
// (Reading::device_values), so their ids read as unknown.
class KnownSettings {
 public:
  std::optional<double> get(WriteTarget target) const {
    if (target.id >= kSettingIdCount) return std::nullopt;
    return values_[target.id];
  }
  void set(WriteTarget target, double value) { values_.at(target.id) = value; }
  void forget(WriteTarget target) { values_.at(target.id).reset(); }

 private:
  std::array<std::optional<double>, kSettingIdCount> values_{};
};

}  // namespace tiltgate
