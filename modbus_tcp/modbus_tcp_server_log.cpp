// ModbusTcpServer's log of clients closed or refused for cause, throttled per address
// (modbus_tcp/log_throttle.h) so a scanner or a broken client cannot flood the log.
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "modbus_tcp/modbus_tcp_server.h"

namespace tiltgate {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

// Called from any thread: the throttle is shared by every connection, under its mutex.
bool ModbusTcpServer::admit_problem(const std::string& address, Clock::time_point now) {
  std::optional<Clock::time_point> due;
  {
    std::lock_guard lock(problem_log_mutex_);
    if (problem_log_.admit(address, now)) return true;
    due = problem_log_.next_summary_due();
  }
  // summarize_suppressed() may sleep past this address's summary.
  if (due) wake_summary_before(*due);
  return false;
}

void ModbusTcpServer::log_closing(const std::string& peer, const std::string& address,
                                  spdlog::level::level_enum level, std::string_view why) {
  const auto now = Clock::now();
  if (admit_problem(address, now)) spdlog::log(level, "closing Modbus TCP client {}: {}", peer, why);
  log_suppressed(now);
}

void ModbusTcpServer::log_problem(const std::string& peer, const std::string& address,
                                  std::string_view what) {
  const auto now = Clock::now();
  if (admit_problem(address, now)) spdlog::warn("Modbus TCP client {}: {}", peer, what);
  log_suppressed(now);
}

void ModbusTcpServer::wake_summary_before(Clock::time_point due) {
  if (due.time_since_epoch().count() >= summary_wake_.load()) return;
  // The timer is the accepting thread's.
  asio::post(executor_, [this] { summary_timer_.cancel(); });
}

void ModbusTcpServer::log_suppressed(Clock::time_point now) {
  std::vector<SuppressedProblems> summaries;
  {
    std::lock_guard lock(problem_log_mutex_);
    summaries = problem_log_.take_summaries(now);
  }
  for (const SuppressedProblems& s : summaries) {
    spdlog::warn("Modbus TCP clients from {}: {} more closed for cause in the last {} s, not "
                 "logged one by one",
                 s.address, s.count,
                 std::chrono::duration_cast<std::chrono::seconds>(s.span).count());
  }
}

// Logs each interval's count of suppressed lines when it ends, also when no further problem
// comes to trigger it.
asio::awaitable<void> ModbusTcpServer::summarize_suppressed() {
  while (running_) {
    const auto now = Clock::now();
    std::optional<Clock::time_point> due;
    {
      std::lock_guard lock(problem_log_mutex_);
      due = problem_log_.next_summary_due();
    }
    const auto wake = due.value_or(now + options()->problem_log.interval);
    summary_timer_.expires_at(wake);
    summary_wake_ = wake.time_since_epoch().count();
    boost::system::error_code ec;
    co_await summary_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (!running_) co_return;
    log_suppressed(Clock::now());
  }
}

}  // namespace tiltgate
