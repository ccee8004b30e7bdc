#include "mapping/map_access.h"

#include <algorithm>
#include <cmath>

#include "mapping/source_values.h"
#include "mapping/value_codec.h"

namespace tiltgate {

namespace {

// Covered points in address order, or illegal_address when a register in the range is not
// mapped or a point sticks out of it (a read that splits a 32-bit value).
Expected<std::span<const Point>, MapFault> covering_points(const RegisterMap& map,
                                                           RegisterTable table,
                                                           std::uint32_t address,
                                                           std::uint32_t count) {
  if (!map.has_table(table)) return Unexpected(MapFault::no_such_table);
  const std::span<const Point> points = map.overlapping(table, address, count);
  std::uint32_t next = address;
  for (const Point& p : points) {
    if (p.address != next) return Unexpected(MapFault::illegal_address);
    next = p.end();
  }
  if (next != address + count) return Unexpected(MapFault::illegal_address);
  return points;
}

bool is_measurement_point(const Point& p) {
  return p.source != ValueSource::bits && is_measurement(p.source);
}

// How measurement points read in this request.
enum class Measurements { fresh, substituted };

Expected<Measurements, MapFault> measurements_for(std::span<const Point> points,
                                                  const SensorView& v) {
  const bool needed = std::any_of(points.begin(), points.end(),
                                  [](const Point& p) { return is_measurement_point(p); });
  if (!needed || (v.online() && !v.stale() && !v.wrong_device())) return Measurements::fresh;
  switch (v.offline) {
    case OfflineRead::exception:
      break;
    case OfflineRead::last_value:
      if (v.state.reading) return Measurements::fresh;
      break;
    case OfflineRead::substitute:
      return Measurements::substituted;
  }
  return Unexpected(MapFault::unavailable);
}

// A float as received is an ordinary number: not NaN, not infinite, and not subnormal. A
// subnormal is what a client that swaps the two words of a float32 sends for an ordinary value
// (0.75 is 3F40 0000; swapped, 0000 3F40 decodes as 2.3e-41), so it is refused rather than
// stored. Zero is a number. Checked on the float itself, before scale and offset.
bool is_ordinary_float(double decoded, PointType type) {
  int kind = FP_NORMAL;
  if (type == PointType::float32) kind = std::fpclassify(float(decoded));  // exact: it was a float
  else if (type == PointType::float64) kind = std::fpclassify(decoded);
  return kind == FP_NORMAL || kind == FP_ZERO;
}

RegisterOrder order_of(const Point& p, WordOrder server) {
  return p.order.value_or(register_order(server));
}

void encode_point(const Point& p, const SensorView& v, Measurements measurements,
                  std::span<std::uint16_t> out) {
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
  double value = point_value(p, v) * p.scale + p.offset;
  if (measurements == Measurements::substituted && is_measurement_point(p))
    value = p.bit ? 0.0 : v.substitute;
  encode_number(out, p.type, value, order_of(p, v.order), p.rounding, p.nan_value);
}

bool bit_value(const Point& p, const SensorView& v, Measurements measurements) {
  if (measurements == Measurements::substituted && is_measurement_point(p)) return false;
  const double value = point_value(p, v);
  return !std::isnan(value) && value != 0;
}

}  // namespace

Expected<Done, MapFault> read_registers(const RegisterMap& map, const SensorView& sensor,
                                        RegisterTable table, std::uint16_t address,
                                        std::span<std::uint16_t> words) {
  const auto count = std::uint32_t(words.size());
  auto points = covering_points(map, table, address, count);
  if (!points) return Unexpected(points.error());
  auto measurements = measurements_for(*points, sensor);
  if (!measurements) return Unexpected(measurements.error());
  for (const Point& p : *points)
    encode_point(p, sensor, *measurements, words.subspan(p.address - address, p.words()));
  return Done{};
}

Expected<Done, MapFault> read_point(const Point& point, const SensorView& sensor,
                                    std::span<std::uint16_t> words) {
  // How measurements read depends on whether the range holds one: for a point alone, on
  // whether it is one, and in any range that holds it, such a point makes it so.
  auto measurements = measurements_for(std::span(&point, 1), sensor);
  if (!measurements) return Unexpected(measurements.error());
  encode_point(point, sensor, *measurements, words);
  return Done{};
}

Expected<std::vector<std::uint16_t>, MapFault> read_registers(const RegisterMap& map,
                                                              const SensorView& sensor,
                                                              RegisterTable table,
                                                              std::uint16_t address,
                                                              std::uint16_t count) {
  std::vector<std::uint16_t> words(count);
  if (auto read = read_registers(map, sensor, table, address, std::span(words)); !read)
    return Unexpected(read.error());
  return words;
}

Expected<Done, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                   RegisterTable table, std::uint16_t address,
                                   std::uint16_t count, std::vector<bool>& bits) {
  auto points = covering_points(map, table, address, count);
  if (!points) return Unexpected(points.error());
  auto measurements = measurements_for(*points, sensor);
  if (!measurements) return Unexpected(measurements.error());
  bits.assign(count, false);  // within its capacity once a first read has grown it
  for (const Point& p : *points) bits[p.address - address] = bit_value(p, sensor, *measurements);
  return Done{};
}

Expected<std::vector<bool>, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                                RegisterTable table, std::uint16_t address,
                                                std::uint16_t count) {
  std::vector<bool> bits;
  if (auto read = read_bits(map, sensor, table, address, count, bits); !read)
    return Unexpected(read.error());
  return bits;
}

Expected<std::vector<PlannedWrite>, MapFault> plan_register_write(
    const RegisterMap& map, WordOrder order, std::uint16_t address,
    std::span<const std::uint16_t> words) {
  auto points = covering_points(map, RegisterTable::holding, address, std::uint32_t(words.size()));
  if (!points) return Unexpected(points.error());
  std::vector<PlannedWrite> plan;
  for (const Point& p : *points) {
    if (!p.write) return Unexpected(MapFault::illegal_address);
    const auto mine = words.subspan(p.address - address, p.words());
    const double decoded = decode_number(mine, p.type, order_of(p, order));
    if (!is_ordinary_float(decoded, p.type)) return Unexpected{MapFault::illegal_value};
    // The inverse of a read's "value * scale + offset"; the loader rejects scale 0.
    const double value = (decoded - p.offset) / p.scale;
    if (!(value >= p.min && value <= p.max)) return Unexpected(MapFault::illegal_value);
    plan.push_back({&p, value, {mine.begin(), mine.end()}});
  }
  return plan;
}

Expected<std::vector<PlannedWrite>, MapFault> plan_point_write(const RegisterMap& map,
                                                               WordOrder order, const Point& point,
                                                               double value) {
  if (point.table != RegisterTable::holding || !point.write || point.type == PointType::string)
    return Unexpected(MapFault::illegal_address);
  // Checked before encoding: an integer register would saturate a value beyond its type.
  if (!(value >= point.min && value <= point.max)) return Unexpected(MapFault::illegal_value);
  std::vector<std::uint16_t> words(point.words());
  encode_number(words, point.type, value * point.scale + point.offset, order_of(point, order),
                point.rounding, point.nan_value);
  return plan_register_write(map, order, point.address, words);
}

}  // namespace tiltgate
