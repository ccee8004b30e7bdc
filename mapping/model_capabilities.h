// What each sensor model offers a register map: its axes, the sources beyond those every
// driver fills (angles, status, counters, identity), and the settings it accepts, as its
// family's descriptor says (driver/family.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "driver/sensor_driver.h"
#include "mapping/value_source.h"

namespace tiltgate {

// Whether a map for `model` may show `source`. A model without a row offers the common
// sources only. angle_y of a single-axis model is offered (it reads NaN, or the point's
// nan_value as an integer), like the default map's.
bool model_offers(std::string_view model, ValueSource source);
// Whether `model` accepts writes of `target`; a model without a row accepts none.
bool model_accepts(std::string_view model, WriteTarget target);
// The number input register 37 shows (ModelDescriptor::model_code); 0 for an unknown model.
std::uint16_t model_code(std::string_view model);
// "CODE PRODUCT, ..." for every model: register 37's description.
std::string model_code_description();
// 1 or 2; 2 for a model without a row (nothing to check against).
int model_axes(std::string_view model);

}  // namespace tiltgate
