// A sensor's triggered bursts (docs/monitoring.md, "Bursts"): it keeps the sensor's samples of
// the last pre_trigger_s, and when a trigger comes (an alarm that sets, or a change faster
// than burst_rate_deg_s) it starts a burst: the caller polls the sensor as fast as its line
// allows for burst_s, and every sample from pre_trigger_s before the trigger to the burst's
// end goes into the burst's record. Pure: fed samples and alarm changes, it says what to
// start and what to write; the caller does the polling and the disk.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "config/config.h"
#include "line_scheduling/sensor_feed.h"

namespace tiltgate::monitoring {

struct BurstStart {
  std::string trigger;          // "alarm x_high warning", "rate 0.8 deg/s"
  std::int64_t unix_ms = 0;     // the triggering sample's
  SteadyClock::time_point until{};  // poll fast until then
  std::vector<FedSample> pre;   // the samples before it, oldest first
};

// What one batch of a sensor's feed meant for its bursts.
struct BurstWork {
  std::optional<BurstStart> started;
  std::vector<FedSample> samples;  // of the running burst, in order (after `started`'s pre)
  bool ended = false;              // the running burst is over after `samples`
};

class BurstRecorder {
 public:
  explicit BurstRecorder(const SensorConfig& sensor);

  // The feed's samples and alarm changes since the last call, in order.
  BurstWork take(const std::vector<FedSample>& samples,
                 const std::vector<FedTransition>& transitions);
  bool running() const { return until_.has_value(); }

 private:
  std::optional<std::string> trigger_at(const FedSample& sample,
                                        const std::vector<FedTransition>& transitions) const;

  std::chrono::seconds burst_;
  std::chrono::seconds pre_trigger_;
  std::optional<double> rate_deg_s_;
  std::deque<FedSample> recent_;  // the last pre_trigger_ of samples
  std::optional<FedSample> last_;
  std::optional<SteadyClock::time_point> until_;
};

}  // namespace tiltgate::monitoring
