#include "mapping/register_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

#include "mapping/map_validation.h"

namespace tiltgate {

RegisterMap::RegisterMap(std::vector<Point> points) : points_(std::move(points)) {
  std::stable_sort(points_.begin(), points_.end(), [](const Point& a, const Point& b) {
    return std::tie(a.table, a.address) < std::tie(b.table, b.address);
  });
}

bool RegisterMap::has_table(RegisterTable table) const {
  return std::any_of(points_.begin(), points_.end(),
                     [&](const Point& p) { return p.table == table; });
}

std::vector<const Point*> RegisterMap::overlapping(RegisterTable table, std::uint32_t address,
                                                   std::uint32_t count) const {
  std::vector<const Point*> found;
  const std::uint32_t end = address + count;
  for (const Point& p : points_) {
    if (p.table == table && p.address < end && p.end() > address) found.push_back(&p);
  }
  return found;
}

const Point* RegisterMap::find(std::string_view name) const {
  for (const Point& p : points_) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::uint32_t RegisterMap::holding_end() const {
  std::uint32_t end = 0;
  for (const Point& p : points_) {
    if (p.table == RegisterTable::holding) end = std::max(end, p.end());
  }
  return end;
}

std::vector<std::string> RegisterMap::validate(FamilyList families, std::string_view model) const {
  std::vector<std::string> messages;
  for (const MapProblem& problem : check_points(points_, families, model))
    messages.push_back(fmt::format("point \"{}\": {}: {}", points_[problem.point].name, problem.key,
                                   problem.message));
  return messages;
}

}  // namespace tiltgate
