#include "gateway/counter_rates.h"

namespace tiltgate {

CounterRates::CounterRates(Clock::duration window, Clock::duration spacing)
    : window_(window), spacing_(spacing) {}

void CounterRates::record(Clock::time_point at, std::vector<double> totals) {
  const std::size_t n = samples_.size();
  if (n >= 2 && samples_[n - 1].at - samples_[n - 2].at < spacing_)
    samples_.back() = {at, std::move(totals)};
  else
    samples_.push_back({at, std::move(totals)});
  // Keep the newest sample that is at least a window old, so the rate covers a whole window.
  while (samples_.size() > 2 && at - samples_[1].at >= window_) samples_.pop_front();
}

void CounterRates::record_restarting(Clock::time_point at, std::vector<double> totals) {
  if (!samples_.empty()) {
    const std::vector<double>& newest = samples_.back().totals;
    for (std::size_t i = 0; i < newest.size() && i < totals.size(); ++i)
      if (totals[i] < newest[i]) {
        samples_.clear();
        break;
      }
  }
  record(at, std::move(totals));
}

std::optional<double> CounterRates::growth(std::size_t index) const {
  if (samples_.size() < 2) return std::nullopt;
  const Sample& first = samples_.front();
  const Sample& last = samples_.back();
  if (index >= first.totals.size() || index >= last.totals.size()) return std::nullopt;
  const double grown = last.totals[index] - first.totals[index];
  if (grown < 0) return std::nullopt;
  return grown;
}

std::optional<double> CounterRates::growth_to(std::size_t index, double total) const {
  if (samples_.empty() || index >= samples_.front().totals.size()) return std::nullopt;
  const double grown = total - samples_.front().totals[index];
  if (grown < 0) return std::nullopt;
  return grown;
}

std::optional<double> CounterRates::rate(std::size_t index) const {
  const std::optional<double> grown = growth(index);
  if (!grown) return std::nullopt;
  const double seconds = std::chrono::duration<double>(samples_.back().at - samples_.front().at).count();
  if (seconds <= 0) return std::nullopt;
  return *grown / seconds;
}

}  // namespace tiltgate
