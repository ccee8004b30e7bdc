// What a sensor's bus hands to the monitoring (monitoring/): every new reading as a sample
// with its UTC time, and every alarm that set or cleared, in order, so that the event record,
// the long record and bursts see all of them whatever the pace of the one who takes them.
//
// The bus's thread puts (one short lock a reading, no I/O); the monitoring's timer takes
// everything put since it last took. Bounded: past `kCapacity` of either kind the oldest is
// dropped and counted, so a monitoring that stalls never grows the gateway's memory.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "driver/sensor_state.h"
#include "line_scheduling/alarm_tracker.h"

namespace tiltgate {

// One reading as the monitoring keeps it: degrees after mounting, NaN where there is none.
struct FedSample {
  std::int64_t unix_ms = 0;   // when its reply arrived, UTC
  SteadyClock::time_point taken{};
  bool clock_synchronised = true;  // the system clock was synchronised then (clock/)
  double x = NAN;
  double y = NAN;
  double tilt = NAN;
  double relative_x = NAN;
  double relative_y = NAN;
  double displacement_mm = NAN;
  double temperature_c = NAN;
  std::uint16_t alarms = 0;         // DerivedState::alarms after it
  std::uint16_t alarms_danger = 0;
};

// An alarm that set or cleared, with the UTC time of the reading it did at.
struct FedTransition {
  AlarmTransition change;
  std::int64_t unix_ms = 0;
};

struct FedBatch {
  std::vector<FedSample> samples;
  std::vector<FedTransition> transitions;
  std::uint64_t dropped = 0;  // samples and transitions lost to the bound since the last take
};

class SensorFeed {
 public:
  static constexpr std::size_t kCapacity = 512;

  void put(const FedSample& sample, const std::vector<AlarmTransition>& changed) {
    std::lock_guard lock(mutex_);
    push_bounded(samples_, sample);
    for (const AlarmTransition& change : changed)
      push_bounded(transitions_, FedTransition{change, sample.unix_ms});
  }

  FedBatch take() {
    FedBatch batch;
    std::lock_guard lock(mutex_);
    batch.samples.assign(samples_.begin(), samples_.end());
    batch.transitions.assign(transitions_.begin(), transitions_.end());
    batch.dropped = dropped_;
    samples_.clear();
    transitions_.clear();
    dropped_ = 0;
    return batch;
  }

 private:
  template <class T>
  void push_bounded(std::deque<T>& queue, const T& item) {
    if (queue.size() == kCapacity) {
      queue.pop_front();
      ++dropped_;
    }
    queue.push_back(item);
  }

  std::mutex mutex_;
  std::deque<FedSample> samples_;
  std::deque<FedTransition> transitions_;
  std::uint64_t dropped_ = 0;
};

}  // namespace tiltgate
