#include "gateway/recent_failures.h"

#include <algorithm>
#include <chrono>

namespace tiltgate {

namespace {

constexpr auto kSpacing = std::chrono::seconds(10);

std::vector<double> as_totals(const FailureCounts& c) {
  return {double(c.polls_failed), double(c.timeouts), double(c.checksum_errors),
          double(c.io_errors), double(c.late_replies)};
}

}  // namespace

void RecentFailures::record(const std::string& sensor, CounterRates::Clock::time_point at,
                            const FailureCounts& totals) {
  auto it = sensors_.find(sensor);
  if (it == sensors_.end())
    it = sensors_.emplace(sensor, CounterRates(kRecentFailuresWindow, kSpacing)).first;
  it->second.record_restarting(at, as_totals(totals));
}

std::optional<FailureCounts> RecentFailures::of(std::string_view sensor,
                                                const FailureCounts& now) const {
  const auto it = sensors_.find(sensor);
  if (it == sensors_.end() || it->second.samples() == 0) return std::nullopt;
  const std::vector<double> totals = as_totals(now);
  std::optional<double> grown[5];
  for (std::size_t i = 0; i < 5; ++i) {
    grown[i] = it->second.growth_to(i, totals[i]);
    // Below the oldest sample: the counters were set back to zero since the newest, less than
    // a sample ago, so all they count is recent.
    if (!grown[i]) return now;
  }
  return FailureCounts{std::uint64_t(*grown[0]), std::uint64_t(*grown[1]), std::uint64_t(*grown[2]),
                       std::uint64_t(*grown[3]), std::uint64_t(*grown[4])};
}

void RecentFailures::forget(std::string_view sensor) {
  if (const auto it = sensors_.find(sensor); it != sensors_.end()) sensors_.erase(it);
}

void RecentFailures::keep_only(const std::vector<std::string>& names) {
  std::erase_if(sensors_, [&](const auto& entry) {
    return std::find(names.begin(), names.end(), entry.first) == names.end();
  });
}

}  // namespace tiltgate
