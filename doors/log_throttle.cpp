#include "doors/log_throttle.h"

#include <algorithm>
#include <utility>

namespace tiltgate {

LogThrottle::LogThrottle(LogThrottleOptions options) : options_(options) {
  options_.max_addresses = std::max<std::size_t>(options_.max_addresses, 1);
}

void LogThrottle::summarize(Window& window, Clock::time_point now) {
  if (window.suppressed == 0) return;
  summaries_.push_back({window.address, window.suppressed, now - window.start});
  window.suppressed = 0;
}

LogThrottle::Window& LogThrottle::window_for(const std::string& address, Clock::time_point now) {
  auto found = std::find_if(windows_.begin(), windows_.end(),
                            [&](const Window& w) { return w.address == address; });
  if (found != windows_.end()) return *found;
  if (windows_.size() >= options_.max_addresses) {
    auto oldest = std::min_element(windows_.begin(), windows_.end(),
                                   [](const Window& a, const Window& b) { return a.start < b.start; });
    summarize(*oldest, now);  // its count is not lost with it
    windows_.erase(oldest);
  }
  windows_.push_back(Window{address, now, 0, 0});
  return windows_.back();
}

bool LogThrottle::admit(const std::string& address, Clock::time_point now) {
  end_intervals(now);  // this address's interval may be over
  Window& window = window_for(address, now);
  if (window.logged < options_.burst) {
    ++window.logged;
    return true;
  }
  ++window.suppressed;
  return false;
}

void LogThrottle::end_intervals(Clock::time_point now) {
  for (auto it = windows_.begin(); it != windows_.end();) {
    if (now - it->start < options_.interval) {
      ++it;
    } else if (it->suppressed > 0) {
      // Still flooding: a new interval, still counted only (no second burst).
      summarize(*it, now);
      it->start = now;
      ++it;
    } else {
      it = windows_.erase(it);  // quiet for an interval: forgotten
    }
  }
}

std::vector<SuppressedProblems> LogThrottle::take_summaries(Clock::time_point now) {
  end_intervals(now);
  return std::exchange(summaries_, {});
}

bool LogThrottle::tracks(std::string_view address) const {
  return std::any_of(windows_.begin(), windows_.end(),
                     [&](const Window& w) { return w.address == address; });
}

std::optional<LogThrottle::Clock::time_point> LogThrottle::next_summary_due() const {
  std::optional<Clock::time_point> due;
  for (const Window& w : windows_)
    if (w.suppressed > 0 && (!due || w.start + options_.interval < *due))
      due = w.start + options_.interval;
  return due;
}

}  // namespace tiltgate
