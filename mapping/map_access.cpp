#include "mapping/map_access.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/value_codec.h"

namespace tiltgate {

bool SensorView::stale() const {
  return !state.reading || now - state.reading->taken > stale_after;
}

std::uint16_t SensorView::age_ms() const {
  if (!state.reading) return 65535;
  const auto age =
      std::chrono::duration_cast<std::chrono::milliseconds>(now - state.reading->taken).count();
  return std::uint16_t(std::clamp<long long>(age, 0, 65535));
}

std::uint16_t SensorView::status() const {
  std::uint16_t bits = 0;
  if (state.online) bits |= status_bit::online;
  if (stale()) bits |= status_bit::stale;
  if (state.last_write_failed) bits |= status_bit::last_write_failed;
  if (!state.identity_known) bits |= status_bit::identity_unknown;
  return bits;
}

namespace {

// Covered points in address order, or illegal_address when a register in the range is not
// mapped or a point sticks out of it (a read that splits a 32-bit value).
Expected<std::vector<const Point*>, MapFault> covering_points(const RegisterMap& map,
                                                              RegisterTable table,
                                                              std::uint32_t address,
                                                              std::uint32_t count) {
  if (!map.has_table(table)) return Unexpected(MapFault::no_such_table);
  auto points = map.overlapping(table, address, count);
  std::uint32_t next = address;
  for (const Point* p : points) {
    if (p->address != next) return Unexpected(MapFault::illegal_address);
    next = p->end();
  }
  if (next != address + count) return Unexpected(MapFault::illegal_address);
  return points;
}

double angle_of(const SensorState& s, bool x) {
  if (!s.reading) return NAN;
  return x ? s.reading->angle_x : s.reading->angle_y;
}

// Numeric value of a source; strings are handled apart.
double numeric_value(ValueSource source, const SensorView& v) {
  const SensorState& s = v.state;
  switch (source) {
    case ValueSource::angle_x:
    case ValueSource::angle_x_cdeg: return angle_of(s, true);
    case ValueSource::angle_y:
    case ValueSource::angle_y_cdeg: return angle_of(s, false);
    case ValueSource::raw_counts:
      return s.reading && s.reading->raw_counts ? double(*s.reading->raw_counts) : NAN;
    case ValueSource::raw_temperature:
      return s.reading && s.reading->raw_temperature ? double(*s.reading->raw_temperature) : NAN;
    case ValueSource::status: return v.status();
    case ValueSource::online: return s.online ? 1 : 0;
    case ValueSource::age_ms: return v.age_ms();
    case ValueSource::polls_ok: return s.counters.polls_ok;
    case ValueSource::polls_failed: return s.counters.polls_failed;
    case ValueSource::last_nak: return s.counters.last_nak ? *s.counters.last_nak : 65535;
    case ValueSource::lock_level: return s.lock_level ? *s.lock_level : 65535;
    case ValueSource::bus_address: return s.bus_address;
    case ValueSource::sample_seq: return s.sample_seq;
    case ValueSource::serial:
    case ValueSource::firmware:
    case ValueSource::written: return NAN;
  }
  return NAN;
}

void encode_point(const Point& p, const SensorView& v, std::span<std::uint16_t> out) {
  if (p.source == ValueSource::written) {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::size_t at = p.address + i;
      out[i] = at < v.written.size() ? v.written[at] : 0;
    }
    return;
  }
  if (p.type == PointType::string) {
    put_string(out, p.source == ValueSource::serial ? v.state.serial : v.state.firmware);
    return;
  }
  const double value = numeric_value(p.source, v);
  switch (p.type) {
    case PointType::float32:
      put_float32(out.first<2>(), float(value), v.order);
      break;
    case PointType::uint32:
      put_uint32(out.first<2>(), std::isnan(value) ? 0 : std::uint32_t(value), v.order);
      break;
    case PointType::int16: {
      const bool cdeg = p.source == ValueSource::angle_x_cdeg || p.source == ValueSource::angle_y_cdeg;
      out[0] = std::uint16_t(saturate_int16(value, cdeg ? 100.0 : 1.0));
      break;
    }
    case PointType::uint16:
    case PointType::boolean:
    case PointType::string:
      out[0] = saturate_uint16(value);
      break;
  }
}

bool needs_fresh_data(const std::vector<const Point*>& points) {
  return std::any_of(points.begin(), points.end(),
                     [](const Point* p) { return is_measurement(p->source); });
}

}  // namespace

Expected<std::vector<std::uint16_t>, MapFault> read_registers(const RegisterMap& map,
                                                              const SensorView& sensor,
                                                              RegisterTable table,
                                                              std::uint16_t address,
                                                              std::uint16_t count) {
  auto points = covering_points(map, table, address, count);
  if (!points) return Unexpected(points.error());
  if (needs_fresh_data(*points) && (!sensor.state.online || sensor.stale())) {
    return Unexpected(MapFault::unavailable);
  }
  std::vector<std::uint16_t> words(count);
  for (const Point* p : *points) {
    encode_point(*p, sensor, std::span(words).subspan(p->address - address, p->words()));
  }
  return words;
}

Expected<std::vector<bool>, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                                RegisterTable table, std::uint16_t address,
                                                std::uint16_t count) {
  auto points = covering_points(map, table, address, count);
  if (!points) return Unexpected(points.error());
  if (needs_fresh_data(*points) && (!sensor.state.online || sensor.stale())) {
    return Unexpected(MapFault::unavailable);
  }
  std::vector<bool> bits(count);
  for (const Point* p : *points) {
    bits[p->address - address] = numeric_value(p->source, sensor) != 0;
  }
  return bits;
}

Expected<std::vector<PlannedWrite>, MapFault> plan_register_write(
    const RegisterMap& map, WordOrder order, std::uint16_t address,
    std::span<const std::uint16_t> words) {
  auto points = covering_points(map, RegisterTable::holding, address,
                                std::uint32_t(words.size()));
  if (!points) return Unexpected(points.error());
  std::vector<PlannedWrite> plan;
  for (const Point* p : *points) {
    if (!p->write) return Unexpected(MapFault::illegal_address);
    const auto mine = words.subspan(p->address - address, p->words());
    double value = 0;
    switch (p->type) {
      case PointType::float32: value = get_float32(mine.first<2>(), order); break;
      case PointType::uint32: value = get_uint32(mine.first<2>(), order); break;
      case PointType::int16: value = std::int16_t(mine[0]); break;
      default: value = mine[0]; break;
    }
    if (!(value >= p->min && value <= p->max)) return Unexpected(MapFault::illegal_value);
    plan.push_back({p, value, {mine.begin(), mine.end()}});
  }
  return plan;
}

}  // namespace tiltgate
