#include "gateway/counter_rates.h"

namespace tiltgate {

CounterRates::CounterRates(Clock::duration window) : window_(window) {}

void CounterRates::record(Clock::time_point at, std::vector<double> totals) {
  samples_.push_back({at, std::move(totals)});
  // Keep the newest sample that is at least a window old, so the rate covers a whole window.
  while (samples_.size() > 2 && at - samples_[1].at >= window_) samples_.pop_front();
}

std::optional<double> CounterRates::rate(std::size_t index) const {
  if (samples_.size() < 2) return std::nullopt;
  const Sample& first = samples_.front();
  const Sample& last = samples_.back();
  if (index >= first.totals.size() || index >= last.totals.size()) return std::nullopt;
  const double seconds = std::chrono::duration<double>(last.at - first.at).count();
  const double growth = last.totals[index] - first.totals[index];
  if (seconds <= 0 || growth < 0) return std::nullopt;
  return growth / seconds;
}

}  // namespace tiltgate
