// The checks a register map must pass before anything serves it: points that overlap or do
// not fit their table, types too small for their scaled source, writes on read-only sources,
// and sources or settings the sensor model does not have. Every problem names the point and
// the map-file key it is about, so config/ can point at the line.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/device_value.h"
#include "driver/family.h"
#include "mapping/point.h"

namespace tiltgate {

struct MapProblem {
  std::size_t point;  // index into the checked points
  std::size_t other;  // the other point of a clash (overlap, duplicate name), or npos
  std::string key;    // "address", "type", "source", ...
  std::string message;
};

inline constexpr std::size_t kNoOtherPoint = static_cast<std::size_t>(-1);

// Every problem of `points` as the map of a sensor of `model` (one of `families`' models) whose
// own values are `device_values` (points resolved against them, mapping/device_values.h);
// model "" skips the checks against a model (mapping/model_capabilities.h) and its values.
std::vector<MapProblem> check_points(std::span<const Point> points, FamilyList families,
                                     std::string_view model,
                                     std::span<const DeviceValue> device_values = {});

}  // namespace tiltgate
