// A register map as a map file (or a [[sensor]]'s inline map) describes it: a built-in
// profile to start from, built-in points to leave out, and points to add or to put in the
// place of built-in ones. Resolved per sensor, because "default" means the sensor's model.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/device_value.h"
#include "mapping/point.h"
#include "mapping/register_map.h"

namespace tiltgate {

// `extends` that means the sensor's own model's built-in map.
inline constexpr std::string_view kDefaultProfile = "default";

struct MapDefinition {
  std::string extends;              // "": start empty; "default"; or a model name
  std::vector<std::string> remove;  // built-in points left out, by name (in every table)
  std::vector<Point> points;        // added; one with a built-in point's name and table
                                    // takes that point's place

  bool operator==(const MapDefinition&) const = default;
};

// A resolved point and where it came from: its index in MapDefinition::points, or kBuiltIn.
inline constexpr std::size_t kBuiltIn = static_cast<std::size_t>(-1);
struct ResolvedPoint {
  Point point;
  std::size_t origin;
};

// The model whose built-in map `definition` starts from ("" when it starts empty).
std::string base_profile(const MapDefinition& definition, std::string_view model);

// The points of `definition` for a sensor of `model` (one of `families`' models) whose own
// values are `device_values` (driver/device_value.h): the kept built-in points, then the
// definition's own, in declaration order, with their device values matched by name
// (mapping/device_values.h).
std::vector<ResolvedPoint> resolve_points(FamilyList families, const MapDefinition& definition,
                                          std::string_view model,
                                          std::span<const DeviceValue> device_values = {});

// A sensor's map: its model's built-in map without a definition, else the resolved definition.
// Register 37 (model_code) is described with every model of `families`.
RegisterMap build_map(FamilyList families, const std::optional<MapDefinition>& definition,
                      std::string_view model, std::span<const DeviceValue> device_values = {});

}  // namespace tiltgate
