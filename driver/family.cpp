#include "driver/family.h"

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

}  // namespace tiltgate
