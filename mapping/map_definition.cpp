#include "mapping/map_definition.h"

#include <algorithm>

#include "mapping/common_block.h"
#include "mapping/default_maps.h"
#include "mapping/device_values.h"
#include "mapping/model_capabilities.h"

namespace tiltgate {

std::string base_profile(const MapDefinition& definition, std::string_view model) {
  if (definition.extends == kDefaultProfile) return std::string(model);
  return definition.extends;
}

std::vector<ResolvedPoint> resolve_points(FamilyList families, const MapDefinition& definition,
                                          std::string_view model,
                                          std::span<const DeviceValue> device_values) {
  std::vector<ResolvedPoint> resolved;
  const std::string base = base_profile(definition, model);
  if (!base.empty()) {
    const RegisterMap builtin = default_map(families, base);
    for (const Point& p : builtin.points()) {
      const auto& removed = definition.remove;
      if (std::any_of(removed.begin(), removed.end(),
                      [&](const std::string& name) { return names_point(name, p.name); }))
        continue;
      const bool replaced = std::any_of(
          definition.points.begin(), definition.points.end(),
          [&](const Point& own) { return names_point(own.name, p.name) && own.table == p.table; });
      // A monitoring point a map of its own overlaps makes way (mapping/common_block.h).
      const bool overlapped = yields_to_map_points(p) &&
          std::any_of(definition.points.begin(), definition.points.end(), [&](const Point& own) {
            return own.table == p.table && own.address < p.end() && p.address < own.end();
          });
      if (!replaced && !overlapped) resolved.push_back({p, kBuiltIn});
    }
  }
  for (std::size_t i = 0; i < definition.points.size(); ++i) {
    resolved.push_back({definition.points[i], i});
    resolve_device_values(std::span(&resolved.back().point, 1), device_values);
  }
  return resolved;
}

RegisterMap build_map(FamilyList families, const std::optional<MapDefinition>& definition,
                      std::string_view model, std::span<const DeviceValue> device_values) {
  std::vector<Point> points;
  if (definition) {
    for (ResolvedPoint& r : resolve_points(families, *definition, model, device_values))
      points.push_back(std::move(r.point));
  } else {
    points = default_map(families, model).points();
  }
  // The common block leaves register 37's description to whoever knows every model.
  for (Point& p : points)
    if (p.source == ValueSource::model_code && p.description.empty())
      p.description = model_code_description(families);
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate
