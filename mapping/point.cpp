#include "mapping/point.h"

#include <vector>

#include "driver/family.h"

namespace tiltgate {

Point make_point(std::string name, RegisterTable table, std::uint16_t address, PointType type,
                 ValueSource source, std::string units, std::string description) {
  Point p;
  p.name = std::move(name);
  p.table = table;
  p.address = address;
  p.type = type;
  p.source = source;
  p.units = std::move(units);
  p.description = std::move(description);
  return p;
}

Point input_point(std::string name, std::uint16_t address, PointType type, ValueSource source,
                  std::string units, std::string description, std::uint16_t chars) {
  Point p = make_point(std::move(name), RegisterTable::input, address, type, source,
                       std::move(units), std::move(description));
  p.chars = chars;
  return p;
}

Point holding_point(std::string name, std::uint16_t address, PointType type, WriteTarget target,
                    double min, double max, std::string units, std::string description) {
  Point p = unavailable_holding_point(std::move(name), address, type, std::move(description));
  p.units = std::move(units);
  p.write = target;
  p.min = min;
  p.max = max;
  return p;
}

Point holding_point(std::uint16_t address, PointType type, const SettingDescriptor& setting) {
  Point p = holding_point(std::string(setting.name), address, type, setting.id, setting.min,
                         setting.max, std::string(setting.unit), std::string(setting.description));
  p.role = setting.role;
  p.operator_values.assign(setting.operator_values.begin(), setting.operator_values.end());
  return p;
}

Point unavailable_holding_point(std::string name, std::uint16_t address, PointType type,
                                std::string description) {
  Point p = make_point(std::move(name), RegisterTable::holding, address, type,
                       ValueSource::setting, "", std::move(description));
  p.nan_value = kUnknownSetting;
  return p;
}

Point discrete_point(std::string name, std::uint16_t address, ValueSource source,
                     std::string description) {
  return make_point(std::move(name), RegisterTable::discrete, address, PointType::boolean, source,
                    "", std::move(description));
}

std::vector<Named<WriteTarget>> write_target_names(FamilyList families) {
  std::vector<Named<WriteTarget>> names;
  const auto add = [&](const SettingDescriptor& setting) {
    for (const Named<WriteTarget>& known : names)
      if (known.name == setting.name) return;
    names.push_back({setting.name, setting.id});
  };
  for (const SettingDescriptor& setting : kCommonSettings) add(setting);
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      for (const SettingDescriptor& setting : model.settings) add(setting);
  return names;
}

std::string setting_name(FamilyList families, WriteTarget target) {
  if (target.is_device_value()) return "the device's value";
  return std::string(name_of(std::span<const Named<WriteTarget>>(write_target_names(families)), target));
}

std::uint16_t Point::words() const {
  switch (type) {
    case PointType::boolean:
    case PointType::uint16:
    case PointType::int16:
      return 1;
    case PointType::uint32:
    case PointType::int32:
    case PointType::float32:
      return 2;
    case PointType::float64:
      return 4;
    case PointType::string:
      return std::uint16_t((chars + 1) / 2);
  }
  return 1;
}

}  // namespace tiltgate
