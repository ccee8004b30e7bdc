// The bursts' samples for the feeds that publish them as historical data (docs/monitoring.md,
// "Bursts"): MQTT <prefix>/<sensor>/burst and Sparkplug DDATA marked historical. Each batch the
// monitoring writes to a burst's file is numbered and kept here for the feeds to take after the
// last they took. Bounded: past kBatchesKept the oldest go, so a feed that stalls never grows
// the gateway's memory (the burst's file keeps it whole).
//
// Threads: the monitoring pushes on the gateway's event loop, the feeds take on it too; one
// mutex, for the feeds a reload makes while the monitoring runs.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "line_scheduling/sensor_feed.h"

namespace tiltgate::monitoring {

struct BurstBatch {
  std::uint64_t seq = 0;
  std::string sensor;
  std::string id;     // the burst's, as its file is named (monitoring/burst_files.h)
  std::string phase;  // "pre" (before the trigger), "trigger" or "burst", as the CSV's
  std::vector<FedSample> samples;
};

class BurstFeed {
 public:
  static constexpr std::size_t kBatchesKept = 256;

  void push(BurstBatch batch) {
    if (batch.samples.empty()) return;
    std::lock_guard lock(mutex_);
    batch.seq = ++last_;
    if (batches_.size() == kBatchesKept) batches_.pop_front();
    batches_.push_back(std::move(batch));
  }

  std::uint64_t last() const {
    std::lock_guard lock(mutex_);
    return last_;
  }

  // The batches numbered after `seq`, oldest first, at most `max`.
  std::vector<BurstBatch> after(std::uint64_t seq, std::size_t max) const {
    std::lock_guard lock(mutex_);
    std::vector<BurstBatch> out;
    for (const BurstBatch& batch : batches_) {
      if (batch.seq <= seq) continue;
      if (out.size() == max) break;
      out.push_back(batch);
    }
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::deque<BurstBatch> batches_;
  std::uint64_t last_ = 0;
};

// What a feed is given: the newest batch's number now (0: none yet), and those after one.
struct BurstSource {
  std::function<std::uint64_t()> last;
  std::function<std::vector<BurstBatch>(std::uint64_t after, std::size_t max)> after;
};

}  // namespace tiltgate::monitoring
