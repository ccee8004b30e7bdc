// The systemd watchdog heartbeat: half of WatchdogSec=, and only for the process systemd meant.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <unistd.h>

#include "app/service_notify.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

// Sets WATCHDOG_USEC and WATCHDOG_PID for one test case, and removes them after it.
struct WatchdogEnvironment {
  WatchdogEnvironment(const std::string& usec, const std::string& pid) {
    setenv("WATCHDOG_USEC", usec.c_str(), 1);
    setenv("WATCHDOG_PID", pid.c_str(), 1);
  }
  ~WatchdogEnvironment() {
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
  }
};

}  // namespace

TEST_CASE("watchdog: the heartbeat comes at half of systemd's interval") {
  CHECK(heartbeat_period(30'000'000) == 15s);
  CHECK(heartbeat_period(3) == 1us);
  CHECK(heartbeat_period(1) == 1us);
  CHECK_FALSE(heartbeat_period(0));
}

TEST_CASE("watchdog: WATCHDOG_USEC for this process starts the heartbeat") {
  const WatchdogEnvironment environment("20000000", std::to_string(getpid()));
  CHECK(watchdog_heartbeat_from_environment() == 10s);
}

TEST_CASE("watchdog: WATCHDOG_USEC meant for another process is not ours") {
  const WatchdogEnvironment environment("20000000", std::to_string(getpid() + 1));
  CHECK_FALSE(watchdog_heartbeat_from_environment());
}

TEST_CASE("watchdog: without WATCHDOG_USEC there is no heartbeat") {
  unsetenv("WATCHDOG_USEC");
  unsetenv("WATCHDOG_PID");
  CHECK_FALSE(watchdog_heartbeat_from_environment());
}
