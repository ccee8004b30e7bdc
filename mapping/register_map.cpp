#include "mapping/register_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

#include "mapping/common_block.h"
#include "mapping/map_validation.h"

namespace tiltgate {

RegisterMap::RegisterMap(std::vector<Point> points) : points_(std::move(points)) {
  std::stable_sort(points_.begin(), points_.end(), [](const Point& a, const Point& b) {
    return std::tie(a.table, a.address) < std::tie(b.table, b.address);
  });
  for (const Point& p : points_) has_table_[std::size_t(p.table)] = true;
}

std::span<const Point> RegisterMap::overlapping(RegisterTable table, std::uint32_t address,
                                                std::uint32_t count) const {
  const std::uint32_t end = address + count;
  const auto before = [](const Point& p, std::pair<RegisterTable, std::uint32_t> at) {
    return std::pair(p.table, std::uint32_t(p.address)) < at;
  };
  // The first point starting at or after `address`; the one before it may still reach in.
  auto first = std::lower_bound(points_.begin(), points_.end(), std::pair(table, address), before);
  if (first != points_.begin()) {
    const auto previous = std::prev(first);
    if (previous->table == table && previous->end() > address) first = previous;
  }
  auto last = std::lower_bound(first, points_.end(), std::pair(table, end), before);
  return {first, last};
}

const Point* RegisterMap::find(std::string_view name) const {
  for (const Point& p : points_) {
    if (p.name == name) return &p;
  }
  // A map or an aggregate written for the address point's former name (mapping/common_block.h).
  if (name == kFormerAddressPointName) return find(kAddressPointName);
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
