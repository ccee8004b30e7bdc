// A register-map point: one named value at a fixed place in one Modbus table of one unit, and
// how it is encoded there.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/family.h"
#include "driver/sensor_driver.h"
#include "mapping/point_types.h"
#include "mapping/value_source.h"

namespace tiltgate {

// Point::device_index before (or without) a match with the sensor's values.
inline constexpr std::uint16_t kNoDeviceValue = 0xFFFF;

struct Point {
  std::string name;
  RegisterTable table = RegisterTable::input;
  std::uint16_t address = 0;  // 0-based protocol address
  PointType type = PointType::uint16;
  std::uint16_t chars = 0;  // strings: characters (two per register)
  ValueSource source = ValueSource::written;
  std::optional<RegisterOrder> order;         // none: the [server] word_order
  AngleUnit angle_unit = AngleUnit::degrees;  // angle sources only
  // Register value = source value * scale + offset (a write is decoded the other way round).
  double scale = 1.0;
  double offset = 0.0;
  Rounding rounding = Rounding::nearest;  // integer types; then saturated at the type's limits
  // Integer types: the map says the source's range may exceed the type, and values beyond it
  // saturate. Without it such a map is rejected.
  bool saturate = false;
  double nan_value = 0.0;           // integer types: what a missing value (NaN) reads as
  std::optional<std::uint8_t> bit;  // this bit (0 = least significant) of an integer source
  std::vector<std::optional<ValueSource>> bits;  // source `bits`: bit i shows bits[i]; none: 0
  std::optional<WriteTarget> write;              // holding points that trigger a sensor write
  // The sensor's own value (driver/device_value.h) that source device_value shows, and the
  // one a write of kUnresolvedDeviceValue writes, by name as the map file gives them; matched
  // with one sensor's values by resolve_device_values() (mapping/device_values.h), which sets
  // device_index and the write's WriteTarget::device_value.
  std::string device_value;
  std::string device_setting;
  std::uint16_t device_index = kNoDeviceValue;
  double min = 0, max = 0;  // writable points: allowed range (inclusive, before scaling)
  // Writable points: who may change the setting (map file key `role`; built-in maps take it
  // from the family's SettingDescriptor). Admin unless marked, so an unmarked custom setting
  // needs an admin. `role_given`: the map file said so, and a device value's own role (its
  // profile's) does not replace it.
  SettingRole role = SettingRole::admin;
  bool role_given = false;
  // Values of an admin setting an operator may write too (map file key `operator_values`;
  // built-in maps: SettingDescriptor::operator_values).
  std::vector<double> operator_values;
  std::string units;
  std::string description;

  std::uint16_t words() const;  // registers (or bits) the point occupies
  std::uint32_t end() const { return std::uint32_t(address) + words(); }

  bool operator==(const Point&) const = default;
};

// A read-only point showing `source`: what built-in maps and tests start from.
Point make_point(std::string name, RegisterTable table, std::uint16_t address, PointType type,
                 ValueSource source, std::string units = {}, std::string description = {});

// The built-in maps' three kinds of point.
Point input_point(std::string name, std::uint16_t address, PointType type, ValueSource source,
                  std::string units, std::string description, std::uint16_t chars = 0);
// What a built-in integer holding register reads while its setting is unknown (floats: NaN).
inline constexpr double kUnknownSetting = 0xFFFF;
// A holding register that triggers `target`, accepting min..max; reads the setting as the
// sensor holds it (SensorState::settings), kUnknownSetting until known.
Point holding_point(std::string name, std::uint16_t address, PointType type, WriteTarget target,
                    double min, double max, std::string units, std::string description);
// The same for a setting as its family describes it: its name, range, unit and meaning.
Point holding_point(std::uint16_t address, PointType type, const SettingDescriptor& setting);
// A holding register of the common block that this model has no setting for: reads
// kUnknownSetting (NaN as a float), and a write is an illegal address like any read-only point.
Point unavailable_holding_point(std::string name, std::uint16_t address, PointType type,
                                std::string description);
Point discrete_point(std::string name, std::uint16_t address, ValueSource source,
                     std::string description);

// The names a map file's `write = "NAME"` uses for a WriteTarget: the common block's settings,
// then every model's own of `families`, each name once.
std::vector<Named<WriteTarget>> write_target_names(FamilyList families);
// A setting's map-file name, for messages.
std::string setting_name(FamilyList families, WriteTarget target);

}  // namespace tiltgate
