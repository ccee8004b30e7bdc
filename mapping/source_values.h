// The value a point shows, from one SensorView: the source's value in the point's angle unit,
// one picked bit, or an integer packed from one-bit sources. Scale and encoding come later
// (mapping/map_access.cpp).
#pragma once

#include "mapping/point.h"
#include "mapping/sensor_view.h"

namespace tiltgate {

// A numeric source's value (NaN when there is none, e.g. angle_y of a single-axis sensor).
// Strings, `written` and `setting` (which need the point) have no single number: NaN.
double source_value(ValueSource source, const SensorView& view);

// The point's value before scale and offset.
double point_value(const Point& point, const SensorView& view);

}  // namespace tiltgate
