#include "mapping/model_capabilities.h"

#include <fmt/format.h>

#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "driver/family.h"

namespace tiltgate {
namespace {

// Reported by some drivers only: listed in a model's sources.
bool is_model_specific(ValueSource source) {
  return source == ValueSource::raw_counts || source == ValueSource::raw_temperature;
}

const ModelDescriptor* find(std::string_view model) {
  return find_model(registered_families(), model).model;
}

template <class T>
bool contains(std::span<const T> list, T value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

}  // namespace

bool model_offers(std::string_view model, ValueSource source) {
  if (!is_model_specific(source)) return true;
  const ModelDescriptor* m = find(model);
  return m != nullptr && contains(m->sources, source);
}

bool model_accepts(std::string_view model, WriteTarget target) {
  const ModelDescriptor* m = find(model);
  if (m == nullptr) return false;
  return std::any_of(m->settings.begin(), m->settings.end(),
                     [&](const SettingDescriptor& s) { return s.id == target; });
}

std::uint16_t model_code(std::string_view model) {
  const ModelDescriptor* m = find(model);
  return m == nullptr ? 0 : m->model_code;
}

int model_axes(std::string_view model) {
  const ModelDescriptor* m = find(model);
  return m == nullptr ? 2 : m->axes;
}

std::string model_code_description() {
  std::vector<std::string> codes;
  for (const FamilyDescriptor* family : registered_families())
    for (const ModelDescriptor& model : family->models)
      codes.push_back(fmt::format("{} {}", model.model_code, model.identity.product_code));
  return fmt::format("{}", fmt::join(codes, ", "));
}

}  // namespace tiltgate
