// What a person reads of a sensor's setting, beyond its map point (docs/web-console.md, "The
// API"): what it is called, a command's values as actions named by what they do, each with the
// question asked before it is sent, and whether the value the gateway shows was read from the
// sensor or is the one last written through the gateway. All of it is the family's to say
// (SettingDescriptor, driver/family.h; a device profile's [[value]] label, driver/device_value.h).
// Pure.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/device_value.h"
#include "driver/family.h"
#include "settings/sensor_settings.h"

namespace tiltgate {

// One value of a command, as a button offers it.
struct SettingAction {
  double value = 0;
  std::string name;     // "Zero permanently"
  std::string confirm;  // the question, the sensor named in it
  SettingRole role = SettingRole::admin;  // who may write it (role_to_write)
};

struct SettingWords {
  std::string label;  // "Bus address"; the setting's name where its family gives none
  std::vector<SettingAction> actions;  // empty but for a command
  // The driver reads it back from the sensor; false: the gateway knows what it last wrote.
  bool read_back = false;
};

// `setting` of a sensor of `model` (none: unknown) whose profile's values are `device_values`,
// its questions naming `sensor`.
SettingWords setting_words(const SensorSetting& setting, const ModelDescriptor* model,
                           std::span<const DeviceValue> device_values, std::string_view sensor);

// `text` with every "{sensor}" replaced by `sensor`.
std::string naming_sensor(std::string_view text, std::string_view sensor);

}  // namespace tiltgate
