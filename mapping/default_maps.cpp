#include "mapping/default_maps.h"

#include <array>
#include <vector>

#include "mapping/common_block.h"
#include "mapping/dyna_map.h"

namespace tiltgate {
namespace {

// The Rieker models have the common block only. Ranges: Rieker function 41 takes 1..6, 38
// codes 1..8, addresses 1..65000; a zero offset beyond the +-180 deg measuring range makes no
// sense.
RegisterMap rieker_map(bool dual_axis) {
  CommonBlockModel m;
  m.dual_axis = dual_axis;
  m.angle_x_description =
      dual_axis ? "X angle after the zero offset and the mounting" : "the single axis angle";
  m.filter = CommonSetting{1, 6, "Set Filter Response 1 (fast, noisy) .. 6 (slow, quiet)"};
  m.zero_x = CommonSetting{-180, 180, "Set Zero To Value, axis 1"};
  if (dual_axis) m.zero_y = CommonSetting{-180, 180, "Set Zero To Value, axis 2"};
  m.command = {1, 3, "1 zero to current angle (temporary), 2 (permanent), 3 restart"};
  m.baud_code = {1, 8, "Set Baud 1..8, takes effect after restart"};
  m.rs485_address = {1, 65000, "Set Address; the gateway follows the sensor"};
  return RegisterMap(common_block(m));
}

RegisterMap h6_map() { return rieker_map(true); }
RegisterMap h4360_map() { return rieker_map(false); }

struct BuiltInMap {
  std::string_view model;
  RegisterMap (*build)();
};

// One row per model with a built-in map.
constexpr std::array<BuiltInMap, 3> kBuiltInMaps{{
    {"h6", h6_map},
    {"h4360", h4360_map},
    {"dyna", dyna_default_map},
}};

}  // namespace

RegisterMap default_map(std::string_view model) {
  for (const BuiltInMap& m : kBuiltInMaps)
    if (m.model == model) return m.build();
  return RegisterMap();
}

std::vector<std::string_view> models_with_default_maps() {
  std::vector<std::string_view> models;
  for (const BuiltInMap& m : kBuiltInMaps) models.push_back(m.model);
  return models;
}

}  // namespace tiltgate
