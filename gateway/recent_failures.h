// Each sensor's failures over the last kRecentFailuresWindow (gateway/gateway_status.h): what the
// console shows beside the counts since start, so one old late reply does not leave a healthy
// sensor looking bad for good (docs/web-console.md, "Counters"). Kept by sensor name, sampled
// with the gateway's other counters once a second and kept 10 s apart (a few KiB a sensor);
// counters that went back to zero (a reset, a sensor made anew by a reload) count from there.
// Pure: the caller says when.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gateway/counter_rates.h"
#include "gateway/gateway_status.h"

namespace tiltgate {

class RecentFailures {
 public:
  // The totals of `sensor` (SensorCounters) at `at`.
  void record(const std::string& sensor, CounterRates::Clock::time_point at,
              const FailureCounts& totals);
  // The sensor's failures from its oldest sample kept (10 minutes ago, or its first) to `now`,
  // its totals as they are: live, so never fewer than its counts since start show when those
  // began less than a sample ago (a reset, a start). None before its first sample.
  std::optional<FailureCounts> of(std::string_view sensor, const FailureCounts& now) const;
  // Forgets the sensor's samples: its counters were set back to zero.
  void forget(std::string_view sensor);
  // Forgets every sensor not in `names` (a reload removed or renamed them).
  void keep_only(const std::vector<std::string>& names);

 private:
  std::map<std::string, CounterRates, std::less<>> sensors_;
};

}  // namespace tiltgate
