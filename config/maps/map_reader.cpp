#include "config/maps/map_reader.h"

#include <fmt/format.h>

#include <algorithm>

#include "config/maps/point_reader.h"
#include "toml/toml_reader.h"
#include "mapping/default_maps.h"
#include "mapping/device_values.h"
#include "mapping/map_validation.h"

namespace tiltgate::config {

using toml_input::place_of;
using toml_input::type_name;
using toml_input::ErrorList;
using toml_input::TableReader;
namespace {

std::string point_path(const std::string& map_path, std::size_t index) {
  return map_path.empty() ? fmt::format("point[{}]", index)
                          : fmt::format("{}.point[{}]", map_path, index);
}

// False when `point` is not an array of tables (a problem of the map, not of one point).
bool read_points(TableReader& in, const std::string& map_path, ParsedMap& map, ErrorList& errors,
                 FamilyList families) {
  const toml::node* node = in.node("point");
  if (node == nullptr) return true;
  const toml::array* array = node->as_array();
  if (array == nullptr) {
    in.error("point", fmt::format("expected an array of tables ([[point]]), got {}",
                                  type_name(node->type())));
    return false;
  }
  bool all_tables = true;
  in.accept("point");
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    if (const toml::table* table = element.as_table()) {
      const std::size_t errors_before = errors.size();
      ParsedPoint point = read_point(*table, point_path(map_path, i), errors, families);
      map.definition.points.push_back(std::move(point.point));
      map.points.push_back(std::move(point.where));
      map.points_read.push_back(errors.size() == errors_before);
    } else {
      errors.add(place_of(element.source()), point_path(map_path, i),
                 fmt::format("expected a table, got {}", type_name(element.type())));
      all_tables = false;
    }
  }
  return all_tables;
}

// Where a problem with a resolved point is reported: at the map's own point (the later one
// of a clash), or at `extends` when only built-in points are involved.
void report(const ParsedMap& map, const std::vector<ResolvedPoint>& resolved,
            const MapProblem& problem, ErrorList& errors) {
  std::size_t origin = resolved[problem.point].origin;
  if (problem.other != kNoOtherPoint && resolved[problem.other].origin != kBuiltIn &&
      (origin == kBuiltIn || resolved[problem.other].origin > origin))
    origin = resolved[problem.other].origin;
  if (origin != kBuiltIn && origin < map.points.size())
    return map.points[origin].report(errors, problem.key, problem.message);
  map.where.report(errors, "extends",
                   fmt::format("built-in point \"{}\": {}: {}", resolved[problem.point].point.name,
                               problem.key, problem.message));
}

void check_removals(const ParsedMap& map, const std::string& base, ErrorList& errors,
                    FamilyList families) {
  const auto& remove = map.definition.remove;
  if (remove.empty()) return;
  if (base.empty())
    return map.where.report(errors, "remove", "nothing to remove: the map extends no built-in map");
  const RegisterMap builtin = default_map(families, base);
  for (const std::string& name : remove)
    if (builtin.find(name) == nullptr)
      map.where.report(errors, "remove",
                       fmt::format("\"{}\" is not a point of the built-in \"{}\" map", name, base));
}

// The part of `map` worth checking: the points that read without errors and, when
// `base_known`, the built-in map it extends and its removals.
ParsedMap readable_part(const ParsedMap& map, bool base_known) {
  ParsedMap part{MapDefinition{}, map.where, {}, {}, map.header_read};
  if (base_known) {
    part.definition.extends = map.definition.extends;
    part.definition.remove = map.definition.remove;
  }
  for (std::size_t i = 0; i < map.points.size(); ++i) {
    if (!map.points_read[i]) continue;
    part.definition.points.push_back(map.definition.points[i]);
    part.points.push_back(map.points[i]);
    part.points_read.push_back(true);
  }
  return part;
}

// A source or setting name that is not built in is matched with the sensor's own values only
// when the map is checked; a point left out of the checks for another key's error still has
// that name checked, so that one run reports both.
void check_unread_names(const ParsedMap& map, std::span<const DeviceValue> device_values,
                        ErrorList& errors, FamilyList families) {
  for (std::size_t i = 0; i < map.points.size(); ++i) {
    if (map.points_read[i]) continue;
    Point point = map.definition.points[i];
    resolve_device_values(std::span(&point, 1), device_values);
    for (const DeviceNameProblem& problem : device_name_problems(families, point, device_values))
      map.points[i].report(errors, problem.key, problem.message);
  }
}

}  // namespace

ParsedMap read_map(const toml::table& table, std::string path, ErrorList& errors,
                   FamilyList families) {
  const std::size_t errors_before = errors.size();
  TableReader in(table, path, errors);
  ParsedMap map{MapDefinition{}, in.located(), {}, {}, true};
  std::vector<std::string_view> profiles{kDefaultProfile};
  for (std::string_view model : models_with_default_maps(families)) profiles.push_back(model);
  if (auto extends = in.choice("extends", profiles)) map.definition.extends = *extends;
  if (auto remove = in.strings("remove")) map.definition.remove = *remove;
  const bool own_keys_read = errors.size() == errors_before;
  const bool points_array_read = read_points(in, path, map, errors, families);
  const std::size_t errors_before_unknown = errors.size();
  in.reject_unknown_keys();
  map.where = in.located();
  map.header_read =
      own_keys_read && points_array_read && errors.size() == errors_before_unknown;
  return map;
}

void check_map(const ParsedMap& map, std::string_view model,
               std::span<const DeviceValue> device_values, ErrorList& errors,
               FamilyList families) {
  const bool base_known =
      map.header_read && !(model.empty() && map.definition.extends == kDefaultProfile);
  const ParsedMap part = readable_part(map, base_known);
  const bool whole = base_known && part.points.size() == map.points.size();
  const std::string base = base_profile(part.definition, model);
  if (base_known && part.definition.extends == kDefaultProfile && default_map(families, base).points().empty())
    return map.where.report(errors, "extends",
                            fmt::format("model \"{}\" has no built-in map to extend", model));
  if (base_known) check_removals(part, base, errors, families);
  if (!model.empty()) check_unread_names(map, device_values, errors, families);
  const std::vector<ResolvedPoint> resolved =
      resolve_points(families, part.definition, model, device_values);
  if (resolved.empty()) {
    if (whole)
      map.where.report(errors, "point",
                       "the map has no points; add [[point]] tables or extends = \"default\"");
    return;
  }
  std::vector<Point> points;
  for (const ResolvedPoint& r : resolved) points.push_back(r.point);
  for (const MapProblem& problem : check_points(points, families, model, device_values))
    report(part, resolved, problem, errors);
}

}  // namespace tiltgate::config
