// A sensor's writable settings as its Sparkplug device shows them (Settings/<name> metrics) and
// a DCMD writes them: the names its register map writes (`write = "filter"`, `zero_x`, ...,
// a sensor's own value by its name), each once, in map order, with the point a write goes to.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/family.h"
#include "driver/sensor_state.h"
#include "mapping/register_map.h"

namespace tiltgate::sparkplug {

struct SensorSetting {
  std::string name;
  const Point* point = nullptr;  // a writable holding point of the map
};

// The settings of `map` (which must outlive the result); a setting two points write (a float
// and an integer register of one value) is listed once, at its first point.
std::vector<SensorSetting> sensor_settings(const RegisterMap& map, FamilyList families);

// The setting's value as the sensor holds it; none while not known.
std::optional<double> setting_value(const SensorSetting& setting, const SensorState& state);

}  // namespace tiltgate::sparkplug
