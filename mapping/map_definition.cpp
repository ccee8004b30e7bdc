#include "mapping/map_definition.h"

#include <algorithm>

#include "mapping/default_maps.h"
#include "mapping/device_values.h"

namespace tiltgate {

std::string base_profile(const MapDefinition& definition, std::string_view model) {
  if (definition.extends == kDefaultProfile) return std::string(model);
  return definition.extends;
}

std::vector<ResolvedPoint> resolve_points(const MapDefinition& definition, std::string_view model,
                                          std::span<const DeviceValue> device_values) {
  std::vector<ResolvedPoint> resolved;
  const std::string base = base_profile(definition, model);
  if (!base.empty()) {
    const RegisterMap builtin = default_map(base);
    for (const Point& p : builtin.points()) {
      const auto& removed = definition.remove;
      if (std::find(removed.begin(), removed.end(), p.name) != removed.end()) continue;
      const bool replaced =
          std::any_of(definition.points.begin(), definition.points.end(),
                      [&](const Point& own) { return own.name == p.name && own.table == p.table; });
      if (!replaced) resolved.push_back({p, kBuiltIn});
    }
  }
  for (std::size_t i = 0; i < definition.points.size(); ++i) {
    resolved.push_back({definition.points[i], i});
    resolve_device_values(std::span(&resolved.back().point, 1), device_values);
  }
  return resolved;
}

RegisterMap build_map(const std::optional<MapDefinition>& definition, std::string_view model,
                      std::span<const DeviceValue> device_values) {
  if (!definition) return default_map(model);
  std::vector<Point> points;
  for (ResolvedPoint& r : resolve_points(*definition, model, device_values))
    points.push_back(std::move(r.point));
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate
