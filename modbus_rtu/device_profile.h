// A Modbus RTU device profile: what to poll from one kind of device ([[read]] blocks, each one
// FC 3/4 request) and what the registers mean ([[value]] entries). Values named angle_x and
// angle_y are the inclination in degrees, one named temperature the device's temperature in
// degrees Celsius; any other value is a source a register-map point can show, and a writable
// one a setting it can write. Loaded from TOML by profile_reader.h;
// decoded here with mapping's value codec, the same one map points use.
//
// Scaling reads from the device's registers to the value: value = raw * scale + offset (the
// opposite direction from a map point's, whose registers are the gateway's own).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/device_value.h"
#include "mapping/point_types.h"
#include "modbus_rtu/codec.h"

namespace tiltgate::modbus_rtu {

struct ReadBlock {
  RegisterBank bank = RegisterBank::input;
  std::uint16_t address = 0;
  std::uint16_t count = 1;
};

struct ProfileValue {
  std::string name;
  RegisterBank bank = RegisterBank::input;
  std::uint16_t address = 0;
  PointType type = PointType::uint16;  // a number type: int16 .. float64
  RegisterOrder order = RegisterOrder::abcd;
  double scale = 1.0;
  double offset = 0.0;
  bool writable = false;  // holding registers only
  // The range a written value must be in (after scaling, as the value reads); none: the type's.
  std::optional<double> min;
  std::optional<double> max;
  // Who may write it (`role`; writable values only): a map point that writes it takes this
  // role unless it gives its own.
  SettingRole role = SettingRole::admin;
  // What a person calls it (`label`; writable values only); empty: its name.
  std::string label{};

  std::uint16_t words() const;  // registers the value takes: 1, 2 or 4
};

// Which values say who the device is ([identity]): each names one of the profile's values, or
// is empty. Shown where the other families show their serial and firmware (API, FC 43, common
// block, Sparkplug).
struct ProfileIdentity {
  std::string serial;
  std::string firmware;
  std::string model;

  bool empty() const { return serial.empty() && firmware.empty() && model.empty(); }
  // Whether `value` is one of the three.
  bool names(std::string_view value) const;
};

struct DeviceProfile {
  std::string path;  // where it was loaded from, for messages
  std::vector<ReadBlock> reads;
  std::vector<ProfileValue> values;
  ProfileIdentity identity;
  // The device's model as people know it ("TLT-2 inclinometer"), shown as its model where the
  // other families show theirs; empty: the identity's model value, when read.
  std::string model_name;

  const ProfileValue* find(std::string_view name) const;
};

// An identity value as text: an integer type in decimal, a float as its shortest decimal
// form; empty when it could not be read (NaN).
std::string identity_text(const ProfileValue& value, double decoded);

// The profile's values as the sensor's own values (driver/device_value.h), in profile order:
// what register-map points may show and write. A writable value's range is its min and max,
// else what its register type holds once scaled.
std::vector<DeviceValue> device_values_of(const DeviceProfile& profile);
DeviceValue device_value_of(const ProfileValue& value);

// Registers a number type takes; 0 for bool and string, which a profile does not offer.
std::uint16_t words_of(PointType type);

// One poll's registers: for each read block in profile order, what it returned, or nullopt when
// its request failed.
using PolledBlocks = std::vector<std::optional<std::vector<std::uint16_t>>>;

struct NamedValue {
  std::string name;
  double value = 0.0;  // NaN when it could not be decoded (its block failed or came back short)
};

// Whether all of `value`'s registers are inside `block`'s.
bool block_holds(const ReadBlock& block, const ProfileValue& value);

// Every value of the profile, in profile order, decoded from one poll.
std::vector<NamedValue> decode_values(const DeviceProfile& profile, const PolledBlocks& blocks);

// The registers that write `value` (as it reads, scale and offset undone; integers rounded to
// nearest and saturated) to `target`.
std::vector<std::uint16_t> encode_value(const ProfileValue& target, double value);

// The request that writes `value` to `target` on `slave`: FC 6 for a one-register value, FC 16
// for a wider one (a device may refuse FC 6 on half of a 32-bit value). The caller checks
// writable and min/max first.
Expected<Request, CodecError> write_request(std::uint8_t slave, const ProfileValue& target,
                                            double value);

}  // namespace tiltgate::modbus_rtu
