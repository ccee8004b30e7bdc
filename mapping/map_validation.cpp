#include "mapping/map_validation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mapping/device_values.h"
#include "mapping/model_capabilities.h"
#include "mapping/value_codec.h"

namespace tiltgate {
namespace {

using S = ValueSource;
using T = PointType;

// Whole numbers in full (4294967295), others to 6 significant digits (3141.59).
std::string number(double value) {
  if (std::isinf(value)) return value < 0 ? "-inf" : "inf";
  if (value == std::trunc(value) && std::fabs(value) < 1e15) return fmt::format("{}", value);
  return fmt::format("{:.6g}", value);
}

bool is_bit_table(RegisterTable table) {
  return table == RegisterTable::coil || table == RegisterTable::discrete;
}

bool is_text_source(ValueSource source) { return source == S::serial || source == S::firmware; }

// Collects the problems of one point.
class PointChecker {
 public:
  PointChecker(const Point& point, std::size_t index, FamilyList families, std::string_view model,
               std::span<const DeviceValue> device_values, std::vector<MapProblem>& problems)
      : p_(point),
        index_(index),
        families_(families),
        model_(model),
        values_(device_values),
        problems_(problems) {}

  void run() {
    check_place();
    check_source();
    check_bits();
    check_write();
    check_encoding();
    check_range();
    if (!model_.empty()) check_model();
  }

 private:
  void report(std::string key, std::string message) {
    problems_.push_back({index_, kNoOtherPoint, std::move(key), std::move(message)});
  }

  void check_place() {
    if (p_.end() > 65536)
      report("address", fmt::format("{} register(s) from {} end past the last address 65535",
                                    p_.words(), p_.address));
    if (is_bit_table(p_.table) != (p_.type == T::boolean))
      report("type", fmt::format("{} does not fit the {} table: bool points go in coil or "
                                 "discrete, numbers and strings in input or holding",
                                 to_string(p_.type), to_string(p_.table)));
    if (p_.type == T::string && p_.chars == 0) report("chars", "a string needs chars = 1..250");
  }

  void check_source() {
    const char* source = to_string(p_.source);
    if ((p_.type == T::string) != is_text_source(p_.source)) {
      if (p_.type == T::string)
        report("source", fmt::format("{} is a number; a string shows serial or firmware", source));
      else
        report("source", fmt::format("{} is text; it needs type = \"string\"", source));
    }
    if (p_.type == T::boolean && !p_.bit && !is_bit_source(p_.source))
      report("source", fmt::format("{} is not one bit: a bool point shows a one-bit source "
                                   "(online, stale, alarm_x_high, ...) or bit = N of an "
                                   "integer source",
                                   source));
    if (p_.bit && !is_integer_source(p_.source))
      report("bit", fmt::format("{} is not an integer, so it has no bits to pick", source));
    if (p_.bit && *p_.bit > 31)
      report("bit", fmt::format("{} is out of range, expected 0..31", *p_.bit));
    if (p_.angle_unit != AngleUnit::degrees && !is_angle_source(p_.source))
      report("angle_unit",
             fmt::format("applies to angle_x, angle_y and tilt only, not {}", source));
  }

  void check_bits() {
    if (p_.source != S::bits) return;
    std::int64_t min = 0, max = 0;
    if (p_.type == T::boolean || !integer_limits(p_.type, min, max)) {
      report("bits", fmt::format("packs bits into an integer register; {} is not one (expected "
                                 "uint16, int16, uint32 or int32)",
                                 to_string(p_.type)));
      return;
    }
    const std::size_t width = 16u * p_.words();
    if (p_.bits.size() > width)
      report("bits", fmt::format("{} bits do not fit a {}, expected at most {}", p_.bits.size(),
                                 to_string(p_.type), width));
    for (const auto& bit : p_.bits)
      if (bit && !is_bit_source(*bit))
        report("bits", fmt::format("{} is not one bit, expected a one-bit source such as "
                                   "online or alarm_x_high",
                                   to_string(*bit)));
    if (p_.scale != 1.0 || p_.offset != 0.0)
      report("scale", "a packed-bits point takes no scale or offset");
  }

  void check_write() {
    if (!p_.write) {
      if (p_.source == S::written)
        report("source",
               "written shows the last value written through the gateway; it needs "
               "a write = \"...\" setting");
      return;
    }
    if (p_.source != S::written && p_.source != S::setting)
      report("write", fmt::format("a writable point shows the value written to it (written) or "
                                  "the sensor's (setting), but its source is the read-only {}; "
                                  "leave source out",
                                  to_string(p_.source)));
    if (p_.table != RegisterTable::holding)
      report("write", fmt::format("writes are served on holding registers only, not in the {} "
                                  "table",
                                  to_string(p_.table)));
    if (p_.type == T::string || p_.type == T::boolean)
      report("type", fmt::format("a writable point needs a numeric register type, not {}",
                                 to_string(p_.type)));
    if (!(p_.min <= p_.max))
      report("min", fmt::format("min {} is greater than max {}", number(p_.min), number(p_.max)));
  }

  void check_encoding() {
    if (p_.order && (p_.type == T::boolean || p_.type == T::string))
      report("word_order",
             fmt::format("applies to numeric register types only, not {}", to_string(p_.type)));
    if (p_.scale == 0.0 || !std::isfinite(p_.scale))
      report("scale", fmt::format("{} is not usable, expected a finite number other than 0 "
                                  "(writes divide by it)",
                                  number(p_.scale)));
    std::int64_t min = 0, max = 0;
    if (p_.type != T::boolean && integer_limits(p_.type, min, max) &&
        (p_.nan_value < double(min) || p_.nan_value > double(max)))
      report("nan_value", fmt::format("{} does not fit {}, expected {}..{}", number(p_.nan_value),
                                      to_string(p_.type), min, max));
  }

  // An integer register must hold every value the source can have, once scaled, unless the
  // map asks for saturation.
  void check_range() {
    std::int64_t min = 0, max = 0;
    if (p_.saturate || p_.bit || p_.type == T::boolean || p_.source == S::bits ||
        !integer_limits(p_.type, min, max) || p_.scale == 0.0)
      return;
    const ValueRange range = source_range(p_.source, p_.angle_unit);
    if (!range.known) return;
    double low = range.min * p_.scale + p_.offset;
    double high = range.max * p_.scale + p_.offset;
    if (low > high) std::swap(low, high);
    const std::string unit = is_angle_source(p_.source)
                                 ? fmt::format(" in {}", name_of(angle_unit_names(), p_.angle_unit))
                                 : std::string();
    const std::string advice = "use a wider type or a smaller scale, or saturate = true to clamp";
    if (std::isinf(low) || std::isinf(high)) {
      report("type", fmt::format("{} cannot hold {}{}: its range has no bounds; {}",
                                 to_string(p_.type), to_string(p_.source), unit, advice));
      return;
    }
    const double low_register = std::round(low);
    const double high_register = std::round(high);
    if (low_register >= double(min) && high_register <= double(max)) return;
    const bool scaled = p_.scale != 1.0 || p_.offset != 0.0;
    const std::string values =
        scaled ? fmt::format("{}..{} * {} + {} = {}..{}", number(range.min), number(range.max),
                             number(p_.scale), number(p_.offset), number(low_register),
                             number(high_register))
               : fmt::format("{}..{}", number(range.min), number(range.max));
    report(scaled ? "scale" : "type",
           fmt::format("{} cannot hold {}{}: {} is beyond {}..{}; {}", to_string(p_.type),
                       to_string(p_.source), unit, values, min, max, advice));
  }

  void check_model() {
    const auto offered = [&](ValueSource s) { return model_offers(families_, model_, s); };
    if (p_.source != S::bits && !offered(p_.source))
      report("source", fmt::format("model \"{}\" does not offer {}", model_, to_string(p_.source)));
    for (const auto& bit : p_.bits)
      if (bit && !offered(*bit))
        report("bits", fmt::format("model \"{}\" does not offer {}", model_, to_string(*bit)));
    if (p_.write && !p_.write->is_device_value() && !model_accepts(families_, model_, *p_.write))
      report("write", fmt::format("model \"{}\" does not accept writes of {}", model_,
                                  setting_name(families_, *p_.write)));
    check_device_values();
  }

  void check_device_values() {
    for (DeviceNameProblem& problem : device_name_problems(families_, p_, values_))
      report(std::move(problem.key), std::move(problem.message));
  }

  const Point& p_;
  std::size_t index_;
  FamilyList families_;
  std::string_view model_;
  std::span<const DeviceValue> values_;
  std::vector<MapProblem>& problems_;
};

// Overlaps within a table (checked on the points in address order) and names used twice in
// one table (the same name in two tables is fine: bus_address reads and sets the address).
void check_layout(std::span<const Point> points, std::vector<MapProblem>& problems) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::pair(points[a].table, points[a].address) <
           std::pair(points[b].table, points[b].address);
  });
  for (std::size_t k = 0; k + 1 < order.size(); ++k) {
    const Point& a = points[order[k]];
    for (std::size_t n = k + 1; n < order.size(); ++n) {
      const Point& b = points[order[n]];
      if (b.table != a.table || b.address >= a.end()) break;
      problems.push_back(
          {order[n], order[k], "address",
           fmt::format("\"{}\" at {} {}..{} overlaps \"{}\" at {}..{}", b.name, to_string(b.table),
                       b.address, b.end() - 1, a.name, a.address, a.end() - 1)});
    }
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (points[j].name != points[i].name || points[j].table != points[i].table) continue;
      problems.push_back({i, j, "name",
                          fmt::format("\"{}\" is used twice in the {} table", points[i].name,
                                      to_string(points[i].table))});
      break;
    }
  }
}

}  // namespace

std::vector<MapProblem> check_points(std::span<const Point> points, FamilyList families,
                                     std::string_view model,
                                     std::span<const DeviceValue> device_values) {
  std::vector<MapProblem> problems;
  for (std::size_t i = 0; i < points.size(); ++i)
    PointChecker(points[i], i, families, model, device_values, problems).run();
  check_layout(points, problems);
  return problems;
}

}  // namespace tiltgate
