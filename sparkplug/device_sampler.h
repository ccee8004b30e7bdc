// Each sensor's state as its Sparkplug device reports it (sparkplug/device_metrics.h
// DeviceSample), taken from the gateway's sensors: the status copy's values
// (gateway/status_copy.h), and what only the edge node shows: the status word, the settings
// and when the reading was taken, in Unix time.
//
// Threads: the gateway's event loop (the buses' thread), between bus events.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "driver/family.h"
#include "gateway/gateway.h"
#include "sparkplug/device_metrics.h"

namespace tiltgate::sparkplug {

class DeviceSampler {
 public:
  DeviceSampler(const Gateway& gateway, FamilyList families);

  // Every sensor the gateway serves now, in configuration order.
  std::vector<DeviceSample> sample(SteadyClock::time_point now, std::int64_t now_unix_ms);

 private:
  // A reading's steady time in Unix ms, through one offset between the clocks: taken afresh at
  // every call, a reading's time would wobble by a millisecond from one sample to the next and
  // look like a new reading. A clock step of more than a second moves the offset.
  std::int64_t unix_ms_of(SteadyClock::time_point taken) const;
  void follow_clock(SteadyClock::time_point now, std::int64_t now_unix_ms);

  const Gateway& gateway_;
  FamilyList families_;
  std::optional<std::int64_t> offset_ms_;  // Unix ms minus steady ms
};

}  // namespace tiltgate::sparkplug
