#include "app/service_notify.h"

#include <algorithm>
#include <fmt/format.h>
#include <systemd/sd-daemon.h>

namespace tiltgate {

std::optional<std::chrono::microseconds> heartbeat_period(std::uint64_t watchdog_usec) {
  if (watchdog_usec == 0) return std::nullopt;
  // At least 1 us: a WatchdogSec of 1 us would otherwise make a timer that never waits.
  return std::chrono::microseconds(std::max<std::uint64_t>(watchdog_usec / 2, 1));
}

std::optional<std::chrono::microseconds> watchdog_heartbeat_from_environment() {
  std::uint64_t usec = 0;
  // 0: keep WATCHDOG_USEC and WATCHDOG_PID in the environment (read again on every call).
  if (sd_watchdog_enabled(0, &usec) <= 0) return std::nullopt;
  return heartbeat_period(usec);
}

ServiceNotifier::ServiceNotifier(boost::asio::io_context& io)
    : timer_(io), period_(watchdog_heartbeat_from_environment()) {}

void ServiceNotifier::ready() {
  sd_notify(0, "READY=1");
  if (period_ && !beating_) {
    beating_ = true;
    beat();
  }
}

void ServiceNotifier::reloading() {
  // MONOTONIC_USEC: the time the reload began, which systemd 253's Type=notify-reload wants
  // with RELOADING=1; systemd 252 (Debian 12) ignores it.
  // steady_clock is CLOCK_MONOTONIC on Linux, the clock systemd means.
  const auto usec = std::chrono::duration_cast<std::chrono::microseconds>(
                        std::chrono::steady_clock::now().time_since_epoch())
                        .count();
  sd_notify(0, fmt::format("RELOADING=1\nMONOTONIC_USEC={}", usec).c_str());
}

void ServiceNotifier::stopping() {
  beating_ = false;
  timer_.cancel();
  sd_notify(0, "STOPPING=1");
}

// On the event loop itself: a loop that hangs sends no more heartbeats.
void ServiceNotifier::beat() {
  sd_notify(0, "WATCHDOG=1");
  timer_.expires_after(*period_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && beating_) beat();
  });
}

}  // namespace tiltgate
