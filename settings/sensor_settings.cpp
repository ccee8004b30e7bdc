#include "settings/sensor_settings.h"

#include <algorithm>
#include <cmath>

namespace tiltgate {

namespace {

SensorSetting setting_of(std::string name, const Point& point) {
  SensorSetting setting;
  setting.name = std::move(name);
  setting.point = &point;
  setting.role = point.role;
  setting.operator_values = point.operator_values;
  setting.min = point.min;
  setting.max = point.max;
  setting.units = point.units;
  setting.description = point.description;
  return setting;
}

}  // namespace

std::vector<SensorSetting> sensor_settings(const RegisterMap& map, FamilyList families,
                                           const SensorState* state) {
  std::vector<SensorSetting> settings;
  for (const Point& point : map.points()) {
    if (point.table != RegisterTable::holding || !point.write || point.type == PointType::string)
      continue;
    std::string name = point.write->is_device_value() ? point.device_setting
                                                      : setting_name(families, *point.write);
    if (name.empty() || *point.write == kUnresolvedDeviceValue) continue;
    const bool listed = std::any_of(settings.begin(), settings.end(),
                                    [&](const SensorSetting& s) { return s.name == name; });
    if (listed) continue;
    settings.push_back(setting_of(std::move(name), point));
    if (state) settings.back().value = setting_value(settings.back(), *state);
  }
  return settings;
}

SettingRole role_to_write(const SensorSetting& setting, double value) {
  const auto& values = setting.operator_values;
  if (std::find(values.begin(), values.end(), value) != values.end()) return SettingRole::operator_;
  return setting.role;
}

std::optional<double> setting_value(const SensorSetting& setting, const SensorState& state) {
  const WriteTarget target = *setting.point->write;
  if (!target.is_device_value()) return state.settings.get(target);
  // A sensor's own values are read with every poll, not kept among the settings.
  if (!state.reading || target.device_index() >= state.reading->device_values.size())
    return std::nullopt;
  const double value = state.reading->device_values[target.device_index()];
  if (std::isnan(value)) return std::nullopt;
  return value;
}

}  // namespace tiltgate
