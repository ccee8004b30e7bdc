// When a device's DDATA is due and which of its metrics it carries (Sparkplug 3.0.0, "report
// by exception", tck-id-topics-ddata-payload): an angle that moved by on_change_deg, any other
// value that changed (status, online, stale, alarms, identity, a setting), and the angles and
// the age on the max_interval heartbeat; never sooner than min_interval after the last. Pure:
// sparkplug/edge_node_session.h keeps what was last reported and sends what this decides.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sparkplug/device_metrics.h"
#include "sparkplug/payload.h"

namespace tiltgate::sparkplug {

struct ExceptionRules {
  double on_change_deg = 0.01;  // 0: every new reading is reported
  std::chrono::milliseconds min_interval{100};
  std::chrono::milliseconds max_interval{10000};
};

// What a device's last message (its DBIRTH or a DDATA) reported, slot by slot of its layout.
struct LastReport {
  std::vector<Value> values;                // empty: nothing reported in this layout yet
  std::optional<std::int64_t> reading;      // the reading's time (Unix ms) it carried
  std::optional<std::chrono::steady_clock::time_point> at;  // when it went out
};

// Whether a message is due for `values` (the device's metrics now, in `layout` order) with
// the reading taken at `reading`.
bool ddata_due(const ExceptionRules& rules, const std::vector<MetricSlot>& layout,
               const LastReport& last, const std::vector<Value>& values,
               std::optional<std::int64_t> reading, std::chrono::steady_clock::time_point now);

// The slots a due message carries: every one when nothing was reported in this layout, else
// those that changed, and the angles and the age as well on the heartbeat, or at a new reading
// when on_change_deg is 0 (a reading, not a change, is then what is reported).
std::vector<std::size_t> ddata_slots(const ExceptionRules& rules,
                                     const std::vector<MetricSlot>& layout, const LastReport& last,
                                     const std::vector<Value>& values,
                                     std::optional<std::int64_t> reading,
                                     std::chrono::steady_clock::time_point now);

}  // namespace tiltgate::sparkplug
