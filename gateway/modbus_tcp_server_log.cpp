// ModbusTcpServer's log of clients closed or refused for cause, throttled per address
// (gateway/log_throttle.h) so a scanner or a broken client cannot flood the log.
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "gateway/modbus_tcp_server.h"

namespace tiltgate {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

void ModbusTcpServer::log_closing(const std::string& peer, const std::string& address,
                                  spdlog::level::level_enum level, std::string_view why) {
  const auto now = Clock::now();
  if (problem_log_.admit(address, now)) {
    spdlog::log(level, "closing Modbus TCP client {}: {}", peer, why);
  } else if (auto due = problem_log_.next_summary_due(); due && *due < summary_timer_.expiry()) {
    summary_timer_.cancel();  // summarize_suppressed() sleeps past this address's summary
  }
  log_suppressed(now);
}

void ModbusTcpServer::log_problem(const std::string& peer, const std::string& address,
                                  std::string_view what) {
  const auto now = Clock::now();
  if (problem_log_.admit(address, now)) {
    spdlog::warn("Modbus TCP client {}: {}", peer, what);
  } else if (auto due = problem_log_.next_summary_due(); due && *due < summary_timer_.expiry()) {
    summary_timer_.cancel();
  }
  log_suppressed(now);
}

void ModbusTcpServer::log_suppressed(Clock::time_point now) {
  for (const SuppressedProblems& s : problem_log_.take_summaries(now)) {
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
    summary_timer_.expires_at(
        problem_log_.next_summary_due().value_or(now + options_.problem_log.interval));
    boost::system::error_code ec;
    co_await summary_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (!running_) co_return;
    log_suppressed(Clock::now());
  }
}

}  // namespace tiltgate
