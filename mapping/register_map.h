// The points one Modbus unit shows, with the lookups the request path needs.
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "mapping/point.h"

namespace tiltgate {

class RegisterMap {
 public:
  RegisterMap() = default;
  // Points may come in any order; overlapping points are a programming or config error and are
  // reported by validate(), not silently accepted.
  explicit RegisterMap(std::vector<Point> points);

  const std::vector<Point>& points() const { return points_; }
  bool has_table(RegisterTable table) const { return has_table_[std::size_t(table)]; }
  // The points of one table that overlap [address, address + count), in address order: a
  // slice of points(), found by binary search (every read asks, so it neither scans the map
  // nor allocates). Exact for a map that validate() accepts, where no two points overlap.
  std::span<const Point> overlapping(RegisterTable table, std::uint32_t address,
                                     std::uint32_t count) const;
  const Point* find(std::string_view name) const;
  // One past the highest holding register, so the gateway can size its written-values shadow.
  std::uint32_t holding_end() const;

  // Empty when the map is consistent (mapping/map_validation.h), also as the map of a sensor
  // of `model` (one of `families`' models) when one is given; otherwise one message per
  // problem.
  std::vector<std::string> validate(FamilyList families = {}, std::string_view model = {}) const;

 private:
  std::vector<Point> points_;  // sorted by (table, address)
  std::array<bool, 4> has_table_{};  // by RegisterTable
};

}  // namespace tiltgate
