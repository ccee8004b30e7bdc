// Per-second rates, and growth, of a set of ever-growing counters (polls, busy seconds, errors)
// over a window, from samples of their totals taken now and then: what the status page shows
// as polls/s, bus use and errors in the last 10 minutes. Pure: the caller says when each sample
// was taken.
#pragma once

#include <chrono>
#include <deque>
#include <optional>
#include <vector>

namespace tiltgate {

class CounterRates {
 public:
  using Clock = std::chrono::steady_clock;

  // `spacing`: samples kept at least that far apart, so a long window sampled often stays
  // small (the newest sample is always the latest totals; it replaces the one before it when
  // that one is closer than `spacing` to the one before it).
  explicit CounterRates(Clock::duration window = std::chrono::seconds(5),
                        Clock::duration spacing = Clock::duration::zero());

  // Records the counters' totals at `at`, in the same order each time. Samples older than the
  // window are forgotten, except the one that spans it.
  void record(Clock::time_point at, std::vector<double> totals);
  // As record(), but first forgets the samples when a counter went down since the newest: the
  // counters were set back to zero (a reset, their sensor made anew) and count from there.
  void record_restarting(Clock::time_point at, std::vector<double> totals);
  // Forgets every sample: after the counters were set back to zero, say.
  void clear() { samples_.clear(); }
  // How many samples are kept: memory a long window takes.
  std::size_t samples() const { return samples_.size(); }

  // Counter `index`'s growth per second from the oldest sample kept to the newest; none with
  // fewer than two samples, a counter missing from either, or one that went down (restarted).
  std::optional<double> rate(std::size_t index) const;
  // Counter `index`'s growth from the oldest sample kept to the newest: over the window once
  // the samples span it, since the first sample before; none as for rate().
  std::optional<double> growth(std::size_t index) const;
  // Counter `index`'s growth from the oldest sample kept to `total`, its value now; none
  // without a sample, or when `total` is below that sample's (the counter restarted since).
  std::optional<double> growth_to(std::size_t index, double total) const;

 private:
  struct Sample {
    Clock::time_point at;
    std::vector<double> totals;
  };
  Clock::duration window_;
  Clock::duration spacing_;
  std::deque<Sample> samples_;
};

}  // namespace tiltgate
