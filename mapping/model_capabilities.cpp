#include "mapping/model_capabilities.h"

#include <algorithm>
#include <array>
#include <vector>

namespace tiltgate {
namespace {

struct ModelCapabilities {
  std::string_view model;
  std::uint16_t code;  // input register 37, model_code: what a PLC program branches on
  int axes;
  // Sources only some drivers fill; every other source is common to all models.
  std::vector<ValueSource> extra_sources;
  std::vector<WriteTarget> writes;
};

using W = WriteTarget;

// Rieker: Set Filter Response (41), Set Zero To Value (16, per axis), the zero/restart
// commands, Set Baud (38) and Set Address (2); the H4360 has one axis.
// Dyna: raw counts and temperature; EEPROM writes (offsets 6, 10, 20, module address 16, baud
// code 22, the EEPROM window) and the reset command; one axis.
const std::array<ModelCapabilities, 3> kModels{{
    {"h6", 1, 2, {}, {W::filter, W::zero_x, W::zero_y, W::command, W::baud_code, W::bus_address}},
    {"h4360", 2, 1, {}, {W::filter, W::zero_x, W::command, W::baud_code, W::bus_address}},
    {"dyna", 3, 1, {ValueSource::raw_counts, ValueSource::raw_temperature},
     {W::sensor_offset, W::temperature_offset, W::pwm_offset, W::eeprom_location,
      W::eeprom_value, W::command, W::baud_code, W::bus_address}},
}};

// Reported by some drivers only: listed in a model's extra_sources.
bool is_model_specific(ValueSource source) {
  return source == ValueSource::raw_counts || source == ValueSource::raw_temperature;
}

const ModelCapabilities* find(std::string_view model) {
  auto it = std::find_if(kModels.begin(), kModels.end(),
                         [&](const ModelCapabilities& m) { return m.model == model; });
  return it == kModels.end() ? nullptr : &*it;
}

template <class T>
bool contains(const std::vector<T>& list, T value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

}  // namespace

bool model_offers(std::string_view model, ValueSource source) {
  if (!is_model_specific(source)) return true;
  const ModelCapabilities* m = find(model);
  return m != nullptr && contains(m->extra_sources, source);
}

bool model_accepts(std::string_view model, WriteTarget target) {
  const ModelCapabilities* m = find(model);
  return m != nullptr && contains(m->writes, target);
}

std::uint16_t model_code(std::string_view model) {
  const ModelCapabilities* m = find(model);
  return m == nullptr ? 0 : m->code;
}

int model_axes(std::string_view model) {
  const ModelCapabilities* m = find(model);
  return m == nullptr ? 2 : m->axes;
}

}  // namespace tiltgate
