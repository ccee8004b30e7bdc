#include "mapping/default_maps.h"

#include "driver/family.h"

namespace tiltgate {

RegisterMap default_map(std::string_view model) {
  const ModelEntry entry = find_model(registered_families(), model);
  return entry.model == nullptr ? RegisterMap() : entry.model->default_map();
}

std::vector<std::string_view> models_with_default_maps() {
  std::vector<std::string_view> models;
  for (const FamilyDescriptor* family : registered_families())
    for (const ModelDescriptor& model : family->models) models.push_back(model.name);
  return models;
}

}  // namespace tiltgate
