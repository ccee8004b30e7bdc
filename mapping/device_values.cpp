#include "mapping/device_values.h"

#include <fmt/format.h>

#include "driver/closest_name.h"

namespace tiltgate {
namespace {

// "did you mean" among the built-in names and the sensor's own, else the choices there are.
template <class E>
std::string unknown_name(const std::string& name, std::span<const Named<E>> built_in,
                         const std::vector<std::string>& own, std::string_view what) {
  std::vector<std::string> known;
  for (const Named<E>& n : built_in) known.emplace_back(n.name);
  known.insert(known.end(), own.begin(), own.end());
  const std::string guess = closest_name(name, known);
  if (!guess.empty()) return fmt::format("\"{}\" is not valid; did you mean \"{}\"?", name, guess);
  if (own.empty())
    return fmt::format("\"{}\" is not valid, expected one of: {}", name, fmt::join(known, ", "));
  return fmt::format("\"{}\" is neither a built-in {} nor one of the sensor's own: {}", name,
                     what, fmt::join(own, ", "));
}

std::vector<std::string> names_of(std::span<const DeviceValue> values, bool writable_only) {
  std::vector<std::string> names;
  for (const DeviceValue& value : values)
    if (value.writable || !writable_only) names.push_back(value.name);
  return names;
}

}  // namespace

std::vector<DeviceNameProblem> device_name_problems(FamilyList families, const Point& p,
                                                    std::span<const DeviceValue> values) {
  std::vector<DeviceNameProblem> problems;
  if (p.source == ValueSource::device_value && p.device_index == kNoDeviceValue)
    problems.push_back({"source", unknown_name(p.device_value, source_names(),
                                               names_of(values, false), "source")});
  if (p.write == kUnresolvedDeviceValue) {
    const std::vector<Named<WriteTarget>> settings = write_target_names(families);
    problems.push_back({"write", unknown_name(p.device_setting,
                                              std::span<const Named<WriteTarget>>(settings),
                                              names_of(values, true), "setting")});
  } else if (p.write && p.write->is_device_value() && p.write->device_index() < values.size() &&
             !values[p.write->device_index()].writable) {
    problems.push_back({"write", fmt::format("\"{}\" is read-only in the sensor's device profile "
                                             "(its [[value]] needs writable = true)",
                                             p.device_setting)});
  }
  return problems;
}

std::optional<std::size_t> find_device_value(std::span<const DeviceValue> values,
                                             std::string_view name) {
  for (std::size_t i = 0; i < values.size() && i < kMaxDeviceValues; ++i)
    if (values[i].name == name) return i;
  return std::nullopt;
}

void resolve_device_values(std::span<Point> points, std::span<const DeviceValue> values) {
  for (Point& p : points) {
    if (p.source == ValueSource::device_value) {
      const auto index = find_device_value(values, p.device_value);
      p.device_index = index ? std::uint16_t(*index) : kNoDeviceValue;
    }
    if (!p.device_setting.empty()) {
      const auto index = find_device_value(values, p.device_setting);
      p.write = index ? WriteTarget::device_value(*index) : kUnresolvedDeviceValue;
      if (index && !p.role_given) p.role = values[*index].role;
    }
  }
}

}  // namespace tiltgate
