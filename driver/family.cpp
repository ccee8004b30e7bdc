#include "driver/family.h"

#include <algorithm>

namespace tiltgate {

ProtocolEntry find_protocol(FamilyList families, std::string_view name) {
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols)
      if (protocol.name == name) return {family, &protocol};
  return {};
}

ModelEntry find_model(FamilyList families, std::string_view name) {
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      if (model.name == name) return {family, &model};
  return {};
}

const ModelDescriptor* first_model_speaking(const FamilyDescriptor& family,
                                           std::string_view protocol) {
  for (const ModelDescriptor& model : family.models)
    if (model.speaks(protocol)) return &model;
  return nullptr;
}

std::vector<std::string_view> model_setting_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      for (const SettingDescriptor& setting : model.settings)
        if (std::find(names.begin(), names.end(), setting.name) == names.end())
          names.push_back(setting.name);
  return names;
}

std::vector<std::string_view> required_sensor_keys(const FamilyDescriptor& family) {
  std::vector<std::string_view> keys;
  for (const SensorKey& key : family.sensor_keys)
    if (key.required) keys.push_back(key.name);
  return keys;
}

bool has_sensor_key(const FamilyDescriptor& family, std::string_view key) {
  return std::any_of(family.sensor_keys.begin(), family.sensor_keys.end(),
                     [&](const SensorKey& k) { return k.name == key; });
}

}  // namespace tiltgate
