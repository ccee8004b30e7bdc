// A TCP server's log of clients closed or refused for cause (the Modbus TCP server's, the HTTP
// server's), throttled per address (doors/log_throttle.h) so a scanner or a broken client
// cannot flood the log: a few lines per address, then only counts, and each interval's count in
// one line when the interval ends.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/common.h>
#include <atomic>
#include <mutex>
#include <string>
#include <string_view>

#include "doors/log_throttle.h"

namespace tiltgate {

// Logged to from any thread (every connection's, the accepting one's): the throttle is shared
// by all of them, under its mutex. The summary timer is the accepting thread's (`executor`,
// single-threaded), and start() and stop() run there.
class ClientProblemLog {
 public:
  using Clock = LogThrottle::Clock;

  // `service` names the server in each line ("Modbus TCP", "HTTP"); with nothing counted, the
  // summary looks again after options.interval.
  ClientProblemLog(boost::asio::any_io_executor executor, std::string service,
                   LogThrottleOptions options);
  ClientProblemLog(const ClientProblemLog&) = delete;
  ClientProblemLog& operator=(const ClientProblemLog&) = delete;

  // Logs why a client is closed, unless its address has had its share of lines lately.
  void log_closing(const std::string& peer, const std::string& address,
                   spdlog::level::level_enum level, std::string_view why);
  // A refused request, throttled with the closes (it is the same client misbehaving).
  void log_problem(const std::string& peer, const std::string& address, std::string_view what);

  // Whether a client from `address` was closed or refused for cause lately (about a minute).
  bool had_problems(const std::string& address);

  // Logs each interval's count of suppressed lines when it ends, also when no further problem
  // comes to trigger it, from start() until stop().
  void start();
  void stop();
  // Its summary loop has ended since stop(): nothing of it is left on the executor.
  bool finished() const { return !summary_running_; }

 private:
  // One problem from `address`: true when it is to be logged in full (else it is counted).
  bool admit_problem(const std::string& address, Clock::time_point now);
  void log_suppressed(Clock::time_point now);
  // summarize_suppressed() is to wake before `due` (from any thread).
  void wake_summary_before(Clock::time_point due);
  boost::asio::awaitable<void> summarize_suppressed();

  boost::asio::any_io_executor executor_;
  const std::string service_;
  const LogThrottleOptions options_;
  std::mutex throttle_mutex_;
  LogThrottle throttle_;
  bool summarizing_ = false;                 // executor_: between start() and stop()
  bool summary_running_ = false;             // executor_: summarize_suppressed() has not ended
  boost::asio::steady_timer summary_timer_;  // executor_: wakes summarize_suppressed()
  std::atomic<Clock::rep> summary_wake_{0};  // summary_timer_'s expiry
};

}  // namespace tiltgate
