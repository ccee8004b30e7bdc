// What each sensor model offers a register map: its axes, the sources beyond those every
// driver fills (angles, status, counters, identity), and the settings it accepts, as its
// family's descriptor says (driver/family.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "driver/device_value.h"
#include "driver/family.h"
#include "driver/sensor_driver.h"
#include "mapping/value_source.h"

namespace tiltgate {

// Each asks about `model`, one of `families`' models.
// Whether a map for `model` may show `source`. A model no family has offers the common
// sources only. angle_y of a single-axis model is offered (it reads NaN, or the point's
// nan_value as an integer), like the default map's.
bool model_offers(FamilyList families, std::string_view model, ValueSource source);
// Whether `model` accepts writes of `target`; a model no family has accepts none.
bool model_accepts(FamilyList families, std::string_view model, WriteTarget target);
// "CODE PRODUCT, ..." for every model of `families`: register 37's description.
std::string model_code_description(FamilyList families);
// 1 or 2; 2 for a model no family has (nothing to check against).
int model_axes(FamilyList families, std::string_view model);
// Whether a sensor of `model` (none: unknown) with these values of its own reports a
// temperature: its model lists the source, or its device profile has a value named
// "temperature". A map may show the source on any model (NaN where there is none); this says
// where there is one, for what describes the sensor (a Sparkplug metric, the console's graph).
bool reports_temperature(const ModelDescriptor* model, std::span<const DeviceValue> values);

}  // namespace tiltgate
