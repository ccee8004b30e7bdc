// Per-second rates of a set of ever-growing counters (polls, busy seconds) over the last few
// seconds, from samples of their totals taken now and then: what the status page shows as
// polls/s and bus use. Pure: the caller says when each sample was taken.
#pragma once

#include <chrono>
#include <deque>
#include <optional>
#include <vector>

namespace tiltgate {

class CounterRates {
 public:
  using Clock = std::chrono::steady_clock;

  explicit CounterRates(Clock::duration window = std::chrono::seconds(5));

  // Records the counters' totals at `at`, in the same order each time. Samples older than the
  // window are forgotten, except the one that spans it.
  void record(Clock::time_point at, std::vector<double> totals);

  // Counter `index`'s growth per second from the oldest sample kept to the newest; none with
  // fewer than two samples, a counter missing from either, or one that went down (restarted).
  std::optional<double> rate(std::size_t index) const;

 private:
  struct Sample {
    Clock::time_point at;
    std::vector<double> totals;
  };
  Clock::duration window_;
  std::deque<Sample> samples_;
};

}  // namespace tiltgate
