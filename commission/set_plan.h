// `tiltgate set SETTING VALUE...` as the writes a model's driver carries out: the engineer's
// words (address, baud, filter, zero-x, zero-y, zero-here, restart, the model's own settings
// and the family's compound ones) turned into SettingWrites through the family's descriptor
// (driver/family_commands.h, SetDescriptor). Pure: nothing is sent; the driver checks the values.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/device_value.h"
#include "driver/expected.h"
#include "driver/family.h"
#include "driver/family_commands.h"
#include "driver/sensor_driver.h"

namespace tiltgate {

// The sensor a setting is for: its family's commands, its bus's protocol, its model and, for a
// family whose sensors describe their own values, those (FamilyOptions::device_values).
struct SetTarget {
  const FamilyCommands* commands = nullptr;
  const ProtocolDescriptor* protocol = nullptr;
  const ModelDescriptor* model = nullptr;
  std::span<const DeviceValue> device_values;
};

struct SetArguments {
  std::vector<std::string> words;  // SETTING VALUE...
  bool permanent = false;          // zero-here --permanent
};

struct SetPlan {
  std::string setting;  // the setting as the engineer named it
  std::vector<SettingWrite> writes;
  // The name each write's setting has in the model's descriptor, for messages.
  std::vector<std::string> write_names;
  std::optional<std::uint32_t> new_address;  // the writes move the sensor to this address
  std::optional<std::uint32_t> new_baud;     // ... and to this rate once restarted
  bool restarts = false;                     // the last write restarts the sensor
};

// "address N", "zero-here [--permanent]", ...: what `tiltgate set` accepts for this sensor.
std::vector<std::string> setting_usages(const SetTarget& target);

// The writes for the arguments, or a usage error (an unknown setting with what it may have
// meant and the model's list, the wrong number of values, a value that is not a number, a baud
// rate the protocol or family does not have).
Expected<SetPlan, std::string> plan_setting(const SetTarget& target, const SetArguments& arguments);

// "1..6", "-180..180 deg": a setting's range, for the messages of a refused value.
std::string range_text(const SettingDescriptor& setting);

}  // namespace tiltgate
