#include "mapping/register_map.h"

#include <algorithm>
#include <fmt/format.h>
#include <tuple>

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

std::vector<std::string> RegisterMap::validate() const {
  std::vector<std::string> problems;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Point& p = points_[i];
    if (p.end() > 65536) {
      problems.push_back(fmt::format("point '{}' ends past address 65535", p.name));
    }
    const bool bit_table = p.table == RegisterTable::coil || p.table == RegisterTable::discrete;
    if (bit_table != (p.type == PointType::boolean)) {
      problems.push_back(fmt::format("point '{}': type {} does not fit the {} table", p.name,
                                     to_string(p.type), to_string(p.table)));
    }
    if (i + 1 < points_.size()) {
      const Point& next = points_[i + 1];
      if (next.table == p.table && next.address < p.end()) {
        problems.push_back(fmt::format("points '{}' and '{}' overlap in the {} table at {}",
                                       p.name, next.name, to_string(p.table), next.address));
      }
    }
  }
  return problems;
}

}  // namespace tiltgate
