// The values one sensor offers beyond the common sources, by name: a generic device's, as its
// device profile describes them (a family that has such sensors reads them with the sensor's
// own keys, driver/family.h). A register-map point shows one with `source = "NAME"` and, when it
// is writable, writes it with `write = "NAME"`. The driver publishes them in this order
// (Reading::device_values) and takes writes of them by WriteTarget::device_value(index).
#pragma once

#include <limits>
#include <string>

#include "driver/setting_role.h"

namespace tiltgate {

struct DeviceValue {
  std::string name;
  bool writable = false;
  // What a written value must be in, as the value reads (the type's limits when the profile
  // gives none).
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  // Who may write it (the profile's `role`); a map point that writes it without a `role` of
  // its own takes this one.
  SettingRole role = SettingRole::admin;
  // What a person calls it (the profile's `label`, else its name): the console's setting label.
  std::string label{};

  bool operator==(const DeviceValue&) const = default;
};

}  // namespace tiltgate
