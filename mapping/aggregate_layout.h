// An aggregate unit's register layout ([[aggregate]], docs/configuration.md, "More than 247 sensors"): the same
// points of many sensors back to back. Sensor i's block starts at register i x block_words;
// within a block the points follow in the order given, each as wide as in the sensors' maps.
// Pure: built from the sensors' register maps, read against their views.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "mapping/map_access.h"
#include "mapping/register_map.h"

namespace tiltgate {

// One point's place in every sensor's block.
struct AggregateSlot {
  std::string point;
  std::uint16_t offset = 0;  // registers from the block's start
  std::uint16_t words = 0;
  PointType type = PointType::uint16;
};

struct AggregateLayout {
  std::vector<AggregateSlot> slots;  // one block, in the order of the points given
  std::uint16_t block_words = 0;
  std::size_t sensors = 0;

  // One past the last register: the aggregate serves [0, end()).
  std::uint32_t end() const { return std::uint32_t(block_words) * std::uint32_t(sensors); }
  std::uint32_t block_start(std::size_t sensor) const {
    return std::uint32_t(sensor) * block_words;
  }
};

// A sensor of an aggregate, as the layout sees it.
struct AggregateMember {
  std::string_view name;
  const RegisterMap* map;
};

// Every point must be an input or holding register point of every member's map, with the same
// type and width in each; the blocks must fit the 65536 registers of a unit. The error names
// the sensor and point ("sensor \"s2\": point \"angle_y\" is int16 (1 register) here but
// float32 (2 registers) in sensor \"s1\"").
Expected<AggregateLayout, std::string> make_aggregate_layout(
    std::span<const std::string> points, std::span<const AggregateMember> members);

// The members whose blocks [address, address + count) touches: [first, last), clipped to
// the members there are.
struct MemberRange {
  std::size_t first = 0, last = 0;
};
MemberRange members_in(const AggregateLayout& layout, std::uint16_t address, std::uint16_t count);

// One member as a read sees it: its map and its view at the request's instant.
struct AggregateSource {
  const RegisterMap* map;
  SensorView view;
};

// Reads [address, address + count) in one pass: `sources` are the members of
// members_in(layout, address, count), in order. Each point reads as it would on the sensor's
// own unit (read_registers: the same offline, stale and substitute rules), so a point that
// would be an exception there makes the request that exception. A range outside the layout
// or splitting a point is illegal_address. Into `words` ([address, address + words.size()),
// the Modbus read path, which allocates nothing), or into a new vector of `count`.
Expected<Done, MapFault> read_aggregate(const AggregateLayout& layout, MemberRange members,
                                        std::span<const AggregateSource> sources,
                                        std::uint16_t address, std::span<std::uint16_t> words);
Expected<std::vector<std::uint16_t>, MapFault> read_aggregate(
    const AggregateLayout& layout, MemberRange members, std::span<const AggregateSource> sources,
    std::uint16_t address, std::uint16_t count);

// The layout as one register map, for `tiltgate map`: each member's points as input registers
// named "SENSOR.POINT" at their place in its block, otherwise as in the member's map.
RegisterMap aggregate_register_map(const AggregateLayout& layout,
                                   std::span<const AggregateMember> members);

}  // namespace tiltgate
