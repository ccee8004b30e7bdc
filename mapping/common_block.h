// The register block every built-in map starts with, at the same addresses on every model, so
// one PLC function block reads any inclinometer: input registers 0..51, holding registers
// 0..7, discrete inputs 0..12 and coil 0. A quantity a model does not have reads its "not available"
// value (NaN, or the integer point's nan_value); a setting it does not have reads 0xFFFF (NaN
// as a float) and refuses writes. Model-specific points start at address 100.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/family.h"
#include "mapping/point.h"

namespace tiltgate {

// First address of the model-specific points, in the input and the holding table.
inline constexpr std::uint16_t kModelSpecificStart = 100;

// What the common block says about one model.
struct CommonBlockModel {
  bool dual_axis = false;
  std::string angle_x_description;  // how the model's angle comes about
  // The same of its Y angle (dual-axis); empty: the family's usual words.
  std::string angle_y_description;
  // Holding registers 0..7, as the model's family describes its settings (range, unit,
  // meaning: driver/family.h); none: not available on this model.
  std::optional<SettingDescriptor> filter, zero_x, zero_y, command, baud_code, bus_address;
};

// The name the common block's address points (input 14, holding 7) had before they took the
// name of the setting they show and write, bus_address: one name everywhere. Where a map file
// or an aggregate names a built-in point, the old name still finds the new (names_point(),
// RegisterMap::find), so maps and configurations written for it keep working
// (docs/register-maps.md, "Default register map").
inline constexpr std::string_view kFormerAddressPointName = "rs485_address";
inline constexpr std::string_view kAddressPointName = "bus_address";

// Whether `given`, a point's name as a map file or an aggregate writes it, names the point
// called `name`: the same name, or the address point's former one.
bool names_point(std::string_view given, std::string_view name);

// The points the block gained with the monitoring (coil 0, discrete inputs 9..12, input
// registers 38..51): a map file written before them may have points of its own there, so where
// a map's own point overlaps one of these, the map's point stays and the built-in one goes
// (mapping/map_definition.cpp). Every older built-in point overlapped is an error, as ever.
bool yields_to_map_points(const Point& builtin);

// The common block's points for one model, in table and address order.
std::vector<Point> common_block(const CommonBlockModel& model);

}  // namespace tiltgate
