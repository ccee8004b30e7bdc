#include "mapping/register_image.h"

#include <algorithm>

namespace tiltgate {

namespace {

// What a register of a rendered table is.
constexpr std::uint8_t kMapped = 1;       // some point's
constexpr std::uint8_t kFirst = 2;        // its point's first register
constexpr std::uint8_t kLast = 4;         // its point's last register
constexpr std::uint8_t kUnavailable = 8;  // its point reads as unavailable in this state
constexpr std::uint8_t kLive = 16;        // its point is read at every read (age_ms)

// The tables rendered, by their index in tables_.
std::size_t index_of(RegisterTable table) { return table == RegisterTable::input ? 0 : 1; }

}  // namespace

Expected<Done, MapFault> RegisterImage::read(const RegisterMap& map, const SensorView& view,
                                             RegisterTable table, std::uint16_t address,
                                             std::span<std::uint16_t> words) {
  if (table != RegisterTable::input && table != RegisterTable::holding)
    return read_registers(map, view, table, address, words);
  if (!map.has_table(table)) return Unexpected(MapFault::no_such_table);
  if (!rendered_ || view.online() != online_ || view.stale() != stale_ || view.order != order_)
    render(map, view);
  if (overlapping_) return read_registers(map, view, table, address, words);
  const Table& rendered = tables_[index_of(table)];
  const std::uint32_t count = std::uint32_t(words.size());
  if (count == 0 || address < rendered.first ||
      address + count > rendered.first + rendered.words.size())
    return Unexpected(MapFault::illegal_address);
  const std::uint32_t at = address - rendered.first;
  const std::span<const std::uint8_t> kinds(rendered.kinds.data() + at, count);
  // Mapped throughout, and no point sticks out at either end: what covering the range whole
  // means (map_access.cpp).
  if (!(kinds.front() & kFirst) || !(kinds.back() & kLast))
    return Unexpected(MapFault::illegal_address);
  std::uint8_t seen = 0;
  for (const std::uint8_t kind : kinds) {
    if (!(kind & kMapped)) return Unexpected(MapFault::illegal_address);
    seen |= kind;
  }
  if (seen & kUnavailable) return Unexpected(MapFault::unavailable);
  std::copy_n(rendered.words.begin() + at, count, words.begin());
  if (seen & kLive) {
    for (const Point* p : live_) {
      if (p->table != table || p->address < address || p->end() > address + count) continue;
      (void)read_point(*p, view, words.subspan(p->address - address, p->words()));
    }
  }
  return Done{};
}

void RegisterImage::render(const RegisterMap& map, const SensorView& view) {
  live_.clear();
  overlapping_ = false;
  render_table(map, view, RegisterTable::input);
  render_table(map, view, RegisterTable::holding);
  rendered_ = true;
  online_ = view.online();
  stale_ = view.stale();
  order_ = view.order;
}

void RegisterImage::render_table(const RegisterMap& map, const SensorView& view,
                                 RegisterTable table) {
  Table& rendered = tables_[index_of(table)];
  const std::span<const Point> points = map.overlapping(table, 0, 0x10000);
  rendered.first = points.empty() ? 0 : points.front().address;
  std::uint32_t end = rendered.first;
  for (const Point& p : points) end = std::max(end, p.end());
  // Within their capacity once a first rendering has grown them.
  rendered.words.assign(end - rendered.first, 0);
  rendered.kinds.assign(end - rendered.first, 0);
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].address < points[i - 1].end()) overlapping_ = true;
  for (const Point& p : points) {
    const std::uint32_t at = p.address - rendered.first;
    const auto read = read_point(p, view, std::span(rendered.words).subspan(at, p.words()));
    std::uint8_t kind = kMapped;
    if (!read) kind |= kUnavailable;  // a measurement of a sensor offline or stale
    if (p.source == ValueSource::age_ms) {
      kind |= kLive;
      live_.push_back(&p);
    }
    for (std::uint32_t i = 0; i < p.words(); ++i) rendered.kinds[at + i] |= kind;
    rendered.kinds[at] |= kFirst;
    rendered.kinds[at + p.words() - 1] |= kLast;
  }
}

}  // namespace tiltgate
