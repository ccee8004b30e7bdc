#include "rieker/default_maps.h"

#include "mapping/common_block.h"
#include "rieker/settings.h"

namespace tiltgate::rieker {
namespace {

// The Rieker models have the common block only, with the settings' ranges from
// rieker/settings.h.
RegisterMap rieker_map(bool dual_axis) {
  CommonBlockModel m;
  m.dual_axis = dual_axis;
  m.angle_x_description =
      dual_axis ? "X angle after the zero offset and the mounting" : "the single axis angle";
  m.filter = settings::filter;
  m.zero_x = settings::zero_x;
  if (dual_axis) m.zero_y = settings::zero_y;
  m.command = settings::command;
  m.baud_code = settings::baud_code;
  m.bus_address = settings::bus_address;
  return RegisterMap(common_block(m));
}

}  // namespace

RegisterMap h6_default_map() { return rieker_map(true); }
RegisterMap h4360_default_map() { return rieker_map(false); }

}  // namespace tiltgate::rieker
