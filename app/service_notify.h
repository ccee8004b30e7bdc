// Telling systemd how `tiltgate run` is doing (Type=notify, sd_notify(3)): READY=1 once the
// listeners are bound and the buses opened, RELOADING=1 then READY=1 around a SIGHUP reload,
// STOPPING=1 at shutdown, and WATCHDOG=1 from the event loop while systemd asks for it
// (WatchdogSec=), so a gateway whose loop hangs is killed and restarted. Without NOTIFY_SOCKET
// (not started by systemd) every call does nothing.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <optional>

namespace tiltgate {

// How often to send WATCHDOG=1: half of systemd's WatchdogSec= (sd_watchdog_enabled(3): half
// leaves room for a late beat), or none when systemd asked for no watchdog.
std::optional<std::chrono::microseconds> heartbeat_period(std::uint64_t watchdog_usec);

// The heartbeat period for this process from WATCHDOG_USEC and WATCHDOG_PID (the watchdog is
// for the process systemd started, not for a child), or none.
std::optional<std::chrono::microseconds> watchdog_heartbeat_from_environment();

class ServiceNotifier {
 public:
  explicit ServiceNotifier(boost::asio::io_context& io);

  // READY=1; the first time, also starts the heartbeat when systemd asked for one.
  void ready();
  // RELOADING=1: a reload has begun; ready() when it is done (applied or refused).
  void reloading();
  // STOPPING=1, and no more heartbeats.
  void stopping();

 private:
  void beat();

  boost::asio::steady_timer timer_;
  std::optional<std::chrono::microseconds> period_;
  bool beating_ = false;
};

}  // namespace tiltgate
