// Failed console logins: free at first, then growing delays per account and per address, up to
// the cap; a success clears them; the tables stay bounded.
#include <doctest/doctest.h>

#include "console/login_throttle.h"

using namespace tiltgate;
using namespace std::chrono_literals;

TEST_CASE("the first failures cost nothing, then each one doubles the wait up to the cap") {
  LoginThrottle throttle;
  const auto t0 = LoginThrottle::Clock::time_point{} + 1000s;
  for (int i = 0; i < LoginThrottle::kFreeFailures; ++i) {
    CHECK_FALSE(throttle.wait("alice", "10.0.0.5", t0));
    throttle.failed("alice", "10.0.0.5", t0);
  }
  CHECK_FALSE(throttle.wait("alice", "10.0.0.5", t0));  // 3 failures: still free
  throttle.failed("alice", "10.0.0.5", t0);
  CHECK(throttle.wait("alice", "10.0.0.5", t0) == 1s);
  throttle.failed("alice", "10.0.0.5", t0 + 1s);
  CHECK(throttle.wait("alice", "10.0.0.5", t0 + 1s) == 2s);
  throttle.failed("alice", "10.0.0.5", t0 + 3s);
  CHECK(throttle.wait("alice", "10.0.0.5", t0 + 3s) == 4s);
  CHECK_FALSE(throttle.wait("alice", "10.0.0.5", t0 + 7s));  // waited it out
  for (int i = 0; i < 20; ++i) throttle.failed("alice", "10.0.0.5", t0 + 10s);
  CHECK(throttle.wait("alice", "10.0.0.5", t0 + 10s) == LoginThrottle::kMaxDelay);
}

TEST_CASE("an account guessed from many addresses, and many accounts from one, are both slowed") {
  LoginThrottle throttle;
  const auto t0 = LoginThrottle::Clock::time_point{} + 1000s;
  for (int i = 0; i < 5; ++i)
    throttle.failed("alice", "10.0.0." + std::to_string(i), t0);
  CHECK(throttle.wait("alice", "10.9.9.9", t0));  // the account
  CHECK_FALSE(throttle.wait("bob", "10.9.9.9", t0));
  for (int i = 0; i < 5; ++i) throttle.failed("user" + std::to_string(i), "10.1.1.1", t0);
  CHECK(throttle.wait("nobody", "10.1.1.1", t0));  // the address
}

TEST_CASE("a success clears the account's and the address's failures") {
  LoginThrottle throttle;
  const auto t0 = LoginThrottle::Clock::time_point{} + 1000s;
  for (int i = 0; i < 5; ++i) throttle.failed("alice", "10.0.0.5", t0);
  throttle.succeeded("alice", "10.0.0.5");
  CHECK_FALSE(throttle.wait("alice", "10.0.0.5", t0));
}

TEST_CASE("a flood of made-up names does not grow the tables past their bound") {
  LoginThrottle throttle;
  const auto t0 = LoginThrottle::Clock::time_point{} + 1000s;
  for (std::size_t i = 0; i < LoginThrottle::kMaxEntries + 100; ++i)
    throttle.failed("u" + std::to_string(i), "10.0.0.5", t0 + std::chrono::seconds(i));
  // The newest names are still counted; the address stays blocked throughout.
  CHECK(throttle.wait("10.0.0.5-unused", "10.0.0.5", t0 + 4200s));
}
