// A sensor's writable settings by name, as every door that changes one shows and writes them
// (Sparkplug's Settings/<name> metrics and DCMD, the console's settings of a sensor): the names
// its register map writes (`write = "filter"`, `zero_x`, ..., a sensor's own value by its name),
// each once, in map order, with the point a write goes to and what a console shows of it.
// Pure: a function of the map and, for the values, the sensor's settings record.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/family.h"
#include "driver/sensor_state.h"
#include "mapping/register_map.h"

namespace tiltgate {

struct SensorSetting {
  std::string name;
  const Point* point = nullptr;  // a writable holding point of the map
  SettingRole role = SettingRole::admin;  // who may change it (the point's role)
  std::vector<double> operator_values;    // of an admin setting, those an operator may write
  // The values a write accepts, inclusive, as a user types them (the point's min and max,
  // before the register's own scale and offset).
  double min = 0;
  double max = 0;
  std::string units;        // the point's
  std::string description;  // the point's: what a write does
  // The sensor's setting as the gateway knows it (setting_value()); none while not known, or
  // when listed without the sensor's state.
  std::optional<double> value;
};

// The settings of `map` (which must outlive the result); a setting two points write (a float
// and an integer register of one value) is listed once, at its first point. With `state`, each
// carries its value as the sensor holds it.
std::vector<SensorSetting> sensor_settings(const RegisterMap& map, FamilyList families,
                                           const SensorState* state = nullptr);

// Who may write `value` to `setting`: its role, or operator for one of its operator_values.
SettingRole role_to_write(const SensorSetting& setting, double value);

// The setting's value as the sensor holds it; none while not known.
std::optional<double> setting_value(const SensorSetting& setting, const SensorState& state);

}  // namespace tiltgate
