#include "sparkplug/report_by_exception.h"

#include <cmath>
#include <variant>

namespace tiltgate::sparkplug {
namespace {

bool is_axis(const MetricSlot& slot) {
  return slot.number == static_cast<std::uint8_t>(DeviceMetric::angle_x) ||
         slot.number == static_cast<std::uint8_t>(DeviceMetric::angle_y);
}

bool is_measurement(const MetricSlot& slot) {
  return slot.angle || !slot.unit.empty() ||
         slot.number == static_cast<std::uint8_t>(DeviceMetric::age_ms);
}

// An angle moved: it appeared, vanished, or changed by `threshold` (> 0) or more.
bool moved(const Value& now, const Value& before, double threshold) {
  const auto* a = std::get_if<double>(&now);
  const auto* b = std::get_if<double>(&before);
  if ((a == nullptr) != (b == nullptr)) return true;
  return a != nullptr && threshold > 0 && std::fabs(*a - *b) >= threshold;
}

bool heartbeat(const ExceptionRules& rules, const LastReport& last,
               std::chrono::steady_clock::time_point now) {
  return last.at && now - *last.at >= rules.max_interval;
}

bool new_reading_reported(const ExceptionRules& rules, const LastReport& last,
                          std::optional<std::int64_t> reading) {
  return rules.on_change_deg == 0 && reading != last.reading;
}

}  // namespace

bool ddata_due(const ExceptionRules& rules, const std::vector<MetricSlot>& layout,
               const LastReport& last, const std::vector<Value>& values,
               std::optional<std::int64_t> reading, std::chrono::steady_clock::time_point now) {
  if (!last.at || last.values.size() != values.size()) return true;
  if (now - *last.at < rules.min_interval) return false;
  if (heartbeat(rules, last, now)) return true;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const MetricSlot& slot = layout[i];
    if (is_axis(slot)) {
      if (moved(values[i], last.values[i], rules.on_change_deg)) return true;
    } else if (!is_measurement(slot) && values[i] != last.values[i]) {
      return true;  // status, online, stale, alarms, identity, a setting
    }
  }
  return new_reading_reported(rules, last, reading);
}

std::vector<std::size_t> ddata_slots(const ExceptionRules& rules,
                                     const std::vector<MetricSlot>& layout, const LastReport& last,
                                     const std::vector<Value>& values,
                                     std::optional<std::int64_t> reading,
                                     std::chrono::steady_clock::time_point now) {
  const bool all = last.values.size() != values.size();
  const bool measurements = heartbeat(rules, last, now) || new_reading_reported(rules, last, reading);
  std::vector<std::size_t> slots;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (all || values[i] != last.values[i] || (measurements && is_measurement(layout[i])))
      slots.push_back(i);
  }
  return slots;
}

}  // namespace tiltgate::sparkplug
