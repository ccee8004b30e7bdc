#include "mapping/aggregate_layout.h"

#include <fmt/format.h>

#include <algorithm>

namespace tiltgate {

namespace {

// The highest register address is 65535: a unit has 65536 registers.
constexpr std::uint32_t kRegisters = 65536;

std::string type_and_width(const Point& p) {
  return fmt::format("{} ({} register{})", to_string(p.type), p.words(), p.words() == 1 ? "" : "s");
}

bool is_register_point(const Point& p) {
  return p.table == RegisterTable::input || p.table == RegisterTable::holding;
}

}  // namespace

Expected<AggregateLayout, std::string> make_aggregate_layout(
    std::span<const std::string> points, std::span<const AggregateMember> members) {
  AggregateLayout layout;
  layout.sensors = members.size();
  if (members.empty()) return Unexpected{std::string("no sensors")};
  std::uint32_t offset = 0;
  for (const std::string& name : points) {
    const Point* first = members.front().map->find(name);
    for (const AggregateMember& member : members) {
      const Point* p = member.map->find(name);
      if (p == nullptr)
        return Unexpected{fmt::format("sensor \"{}\": its map has no point \"{}\"", member.name,
                                      name)};
      if (!is_register_point(*p))
        return Unexpected{fmt::format("sensor \"{}\": point \"{}\" is a {} point, expected an "
                                      "input or holding register point",
                                      member.name, name, to_string(p->table))};
      if (p->type != first->type || p->words() != first->words())
        return Unexpected{fmt::format("sensor \"{}\": point \"{}\" is {} here but {} in sensor "
                                      "\"{}\"; an aggregate's point must be the same in every "
                                      "sensor's map",
                                      member.name, name, type_and_width(*p), type_and_width(*first),
                                      members.front().name)};
    }
    layout.slots.push_back({name, std::uint16_t(offset), first->words(), first->type});
    offset += first->words();
    if (offset >= kRegisters) break;
  }
  if (offset * members.size() > kRegisters)
    return Unexpected{fmt::format("{} sensors x {} registers is {} registers, more than the {} "
                                  "a Modbus unit has",
                                  members.size(), offset, offset * members.size(), kRegisters)};
  layout.block_words = std::uint16_t(offset);
  return layout;
}

MemberRange members_in(const AggregateLayout& layout, std::uint16_t address,
                       std::uint16_t count) {
  if (layout.block_words == 0 || count == 0) return {};
  const std::size_t first = address / layout.block_words;
  const std::size_t last = (std::uint32_t(address) + count - 1) / layout.block_words + 1;
  return {std::min(first, layout.sensors), std::min(last, layout.sensors)};
}

Expected<Done, MapFault> read_aggregate(const AggregateLayout& layout, MemberRange members,
                                        std::span<const AggregateSource> sources,
                                        std::uint16_t address, std::span<std::uint16_t> words) {
  const std::uint32_t end = std::uint32_t(address) + std::uint32_t(words.size());
  if (words.empty() || end > layout.end()) return Unexpected{MapFault::illegal_address};
  if (sources.size() != members.last - members.first) return Unexpected{MapFault::illegal_address};
  for (std::size_t i = members.first; i < members.last; ++i) {
    const AggregateSource& source = sources[i - members.first];
    const std::uint32_t base = layout.block_start(i);
    for (const AggregateSlot& slot : layout.slots) {
      const std::uint32_t start = base + slot.offset;
      const std::uint32_t stop = start + slot.words;
      if (stop <= address || start >= end) continue;
      // A read that splits a 32-bit value is refused, as on a sensor's own unit.
      if (start < address || stop > end) return Unexpected{MapFault::illegal_address};
      const Point* p = source.map->find(slot.point);
      if (p == nullptr) return Unexpected{MapFault::illegal_address};  // the loader checks
      auto read = read_registers(*source.map, source.view, p->table, p->address,
                                 words.subspan(start - address, p->words()));
      if (!read) return Unexpected{read.error()};
    }
  }
  return Done{};
}

Expected<std::vector<std::uint16_t>, MapFault> read_aggregate(
    const AggregateLayout& layout, MemberRange members, std::span<const AggregateSource> sources,
    std::uint16_t address, std::uint16_t count) {
  std::vector<std::uint16_t> words(count);
  auto read = read_aggregate(layout, members, sources, address, words);
  if (!read) return Unexpected{read.error()};
  return words;
}

RegisterMap aggregate_register_map(const AggregateLayout& layout,
                                   std::span<const AggregateMember> members) {
  std::vector<Point> points;
  for (std::size_t i = 0; i < members.size() && i < layout.sensors; ++i) {
    for (const AggregateSlot& slot : layout.slots) {
      const Point* original = members[i].map->find(slot.point);
      if (original == nullptr) continue;
      Point p = *original;
      p.name = fmt::format("{}.{}", members[i].name, slot.point);
      p.table = RegisterTable::input;
      p.address = std::uint16_t(layout.block_start(i) + slot.offset);
      p.write.reset();
      points.push_back(std::move(p));
    }
  }
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate
