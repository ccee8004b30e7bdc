#include "doors/client_problem_log.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <optional>
#include <spdlog/spdlog.h>
#include <vector>

#include "driver/visible_text.h"

namespace tiltgate {

namespace asio = boost::asio;

ClientProblemLog::ClientProblemLog(asio::any_io_executor executor, std::string service,
                                   LogThrottleOptions options)
    : executor_(executor),
      service_(std::move(service)),
      options_(options),
      throttle_(options),
      summary_timer_(executor) {}

// Called from any thread: the throttle is shared by every connection, under its mutex.
bool ClientProblemLog::admit_problem(const std::string& address, Clock::time_point now) {
  std::optional<Clock::time_point> due;
  {
    std::lock_guard lock(throttle_mutex_);
    if (throttle_.admit(address, now)) return true;
    due = throttle_.next_summary_due();
  }
  // summarize_suppressed() may sleep past this address's summary.
  if (due) wake_summary_before(*due);
  return false;
}

void ClientProblemLog::log_closing(const std::string& peer, const std::string& address,
                                   spdlog::level::level_enum level, std::string_view why) {
  const auto now = Clock::now();
  if (admit_problem(address, now))
    spdlog::log(level, "closing {} client {}: {}", service_, visible_text(peer), visible_text(why));
  log_suppressed(now);
}

void ClientProblemLog::log_problem(const std::string& peer, const std::string& address,
                                   std::string_view what) {
  const auto now = Clock::now();
  if (admit_problem(address, now))
    spdlog::warn("{} client {}: {}", service_, visible_text(peer), visible_text(what));
  log_suppressed(now);
}

bool ClientProblemLog::had_problems(const std::string& address) {
  std::lock_guard lock(throttle_mutex_);
  return throttle_.tracks(address);
}

void ClientProblemLog::wake_summary_before(Clock::time_point due) {
  if (due.time_since_epoch().count() >= summary_wake_.load()) return;
  // The timer is the accepting thread's.
  asio::post(executor_, [this] { summary_timer_.cancel(); });
}

void ClientProblemLog::log_suppressed(Clock::time_point now) {
  std::vector<SuppressedProblems> summaries;
  {
    std::lock_guard lock(throttle_mutex_);
    summaries = throttle_.take_summaries(now);
  }
  for (const SuppressedProblems& s : summaries) {
    spdlog::warn("{} clients from {}: {} more closed for cause in the last {} s, not logged one "
                 "by one",
                 service_, s.address, s.count,
                 std::chrono::duration_cast<std::chrono::seconds>(s.span).count());
  }
}

void ClientProblemLog::start() {
  summarizing_ = true;
  summary_running_ = true;
  asio::co_spawn(executor_, summarize_suppressed(),
                 [this](std::exception_ptr) { summary_running_ = false; });
}

void ClientProblemLog::stop() {
  summarizing_ = false;
  summary_timer_.cancel();
}

asio::awaitable<void> ClientProblemLog::summarize_suppressed() {
  while (summarizing_) {
    const auto now = Clock::now();
    std::optional<Clock::time_point> due;
    {
      std::lock_guard lock(throttle_mutex_);
      due = throttle_.next_summary_due();
    }
    const auto wake = due.value_or(now + options_.interval);
    summary_timer_.expires_at(wake);
    summary_wake_ = wake.time_since_epoch().count();
    boost::system::error_code ec;
    co_await summary_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (!summarizing_) co_return;
    log_suppressed(Clock::now());
  }
}

}  // namespace tiltgate
