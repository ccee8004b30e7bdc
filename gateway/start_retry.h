// A service's part that could not start (its state_dir or socket folder not writable by the
// serving user, say) is tried again every kInterval until it starts, so fixing the cause needs
// neither a restart nor a reload. On the event loop's thread only.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>

namespace tiltgate {

class StartRetry {
 public:
  static constexpr std::chrono::seconds kInterval{10};

  explicit StartRetry(boost::asio::any_io_executor executor) : timer_(std::move(executor)) {}
  StartRetry(const StartRetry&) = delete;
  StartRetry& operator=(const StartRetry&) = delete;

  // Calls `attempt` kInterval from now, and again after each time it returns false.
  void schedule(std::function<bool()> attempt) {
    attempt_ = std::move(attempt);
    timer_.expires_after(kInterval);
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;  // cancelled, or destroyed with its service: nothing of this is touched
      if (!attempt_()) schedule(std::move(attempt_));
    });
  }
  void cancel() { timer_.cancel(); }

 private:
  boost::asio::steady_timer timer_;
  std::function<bool()> attempt_;
};

}  // namespace tiltgate
