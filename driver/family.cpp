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

std::vector<std::string_view> model_setting_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      for (const SettingDescriptor& setting : model.settings)
        if (std::find(names.begin(), names.end(), setting.name) == names.end())
          names.push_back(setting.name);
  return names;
}

}  // namespace tiltgate
