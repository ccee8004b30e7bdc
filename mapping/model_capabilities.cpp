#include "mapping/model_capabilities.h"

#include <fmt/format.h>

#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "mapping/device_values.h"

namespace tiltgate {
namespace {

// Reported by some drivers only: listed in a model's sources.
bool is_model_specific(ValueSource source) {
  return source == ValueSource::raw_counts || source == ValueSource::raw_temperature;
}

const ModelDescriptor* find(FamilyList families, std::string_view model) {
  return find_model(families, model).model;
}

template <class T>
bool contains(std::span<const T> list, T value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

}  // namespace

bool model_offers(FamilyList families, std::string_view model, ValueSource source) {
  if (!is_model_specific(source)) return true;
  const ModelDescriptor* m = find(families, model);
  return m != nullptr && contains(m->sources, source);
}

bool model_accepts(FamilyList families, std::string_view model, WriteTarget target) {
  const ModelDescriptor* m = find(families, model);
  if (m == nullptr) return false;
  return std::any_of(m->settings.begin(), m->settings.end(),
                     [&](const SettingDescriptor& s) { return s.id == target; });
}

bool reports_temperature(const ModelDescriptor* model, std::span<const DeviceValue> values) {
  return (model != nullptr && contains(model->sources, ValueSource::temperature)) ||
         find_device_value(values, "temperature").has_value();
}

int model_axes(FamilyList families, std::string_view model) {
  const ModelDescriptor* m = find(families, model);
  return m == nullptr ? 2 : m->axes;
}

std::string model_code_description(FamilyList families) {
  std::vector<std::string> codes;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      codes.push_back(fmt::format("{} {}", model.model_code, model.identity.product_code));
  return fmt::format("{}", fmt::join(codes, ", "));
}

}  // namespace tiltgate
