#include "mapping/default_maps.h"

namespace tiltgate {

RegisterMap default_map(FamilyList families, std::string_view model) {
  const ModelEntry entry = find_model(families, model);
  return entry.model == nullptr ? RegisterMap() : entry.model->default_map();
}

std::vector<std::string_view> models_with_default_maps(FamilyList families) {
  std::vector<std::string_view> models;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models) models.push_back(model.name);
  return models;
}

}  // namespace tiltgate
