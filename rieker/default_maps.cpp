#include "rieker/default_maps.h"

#include "mapping/common_block.h"

namespace tiltgate::rieker {
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

}  // namespace

RegisterMap h6_default_map() { return rieker_map(true); }
RegisterMap h4360_default_map() { return rieker_map(false); }

}  // namespace tiltgate::rieker
