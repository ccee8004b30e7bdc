// Keeps one misbehaving client from flooding the log: per client address, the first `burst`
// problems are logged one by one; past that they are only counted, and each interval that
// counted some ends in one summary line. An address quiet for a whole interval starts afresh.
// Pure (time is passed in), so the policy is tested without sockets or clocks.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

struct LogThrottleOptions {
  std::size_t burst = 5;                          // problems logged in full per address
  std::chrono::steady_clock::duration interval = std::chrono::seconds(60);
  std::size_t max_addresses = 256;  // tracked at once; a new one evicts the oldest
};

// What was not logged: `count` problems from `address` in the `span` before the summary.
struct SuppressedProblems {
  std::string address;
  std::uint64_t count = 0;
  std::chrono::steady_clock::duration span{};
};

class LogThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  explicit LogThrottle(LogThrottleOptions options = {});

  // One problem from `address` at `now`: true when it is to be logged in full.
  bool admit(const std::string& address, Clock::time_point now);
  // The counts of the intervals that ended by `now`, and of addresses evicted to make room:
  // one summary each, to be logged. Call after admit() and when next_summary_due() comes.
  std::vector<SuppressedProblems> take_summaries(Clock::time_point now);
  // The end of the earliest interval that has counted problems; none when nothing is counted.
  std::optional<Clock::time_point> next_summary_due() const;
  std::size_t tracked_addresses() const { return windows_.size(); }
  // Whether `address` had a problem in its current interval (or the one before, until the
  // next call that ends intervals).
  bool tracks(std::string_view address) const;

 private:
  struct Window {
    std::string address;
    Clock::time_point start;
    std::size_t logged = 0;
    std::uint64_t suppressed = 0;
  };

  Window& window_for(const std::string& address, Clock::time_point now);
  void summarize(Window& window, Clock::time_point now);
  // Summarizes every interval over by `now`; forgets the addresses quiet throughout theirs.
  void end_intervals(Clock::time_point now);

  LogThrottleOptions options_;
  std::vector<Window> windows_;  // at most max_addresses: a linear search is cheap enough
  std::vector<SuppressedProblems> summaries_;
};

}  // namespace tiltgate
