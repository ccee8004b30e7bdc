// Who may try a console password now (console/login_throttle.h; issue 52, item 5): per address,
// free at first, then growing delays up to the cap; per account, at most 10 guesses a minute
// from everywhere, of which addresses with failures share 5, so the owner from a clean address
// still gets in; everything counted before the hash; the tables bounded.
#include <doctest/doctest.h>

#include "console/login_throttle.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Clock = LoginThrottle::Clock;
const Clock::time_point t0 = Clock::time_point{} + 1000s;

bool admitted(const std::variant<LoginThrottle::Admitted, LoginThrottle::Refused>& answer) {
  return std::holds_alternative<LoginThrottle::Admitted>(answer);
}

LoginThrottle::Refused refused(const std::variant<LoginThrottle::Admitted, LoginThrottle::Refused>& answer) {
  REQUIRE(std::holds_alternative<LoginThrottle::Refused>(answer));
  return std::get<LoginThrottle::Refused>(answer);
}

}  // namespace

TEST_CASE("from one address the first failures cost nothing, then each doubles the wait up to the cap") {
  LoginThrottle throttle;
  // Different names each time: the address alone is counted here.
  int n = 0;
  const auto next = [&](Clock::time_point at) {
    return throttle.admit("u" + std::to_string(n++), false, "10.0.0.5", at);
  };
  for (int i = 0; i < LoginThrottle::kFreeFailures; ++i) CHECK(admitted(next(t0)));
  CHECK(admitted(next(t0)));  // 3 failures: still free
  CHECK(refused(next(t0)).wait == 1s);
  CHECK(refused(next(t0)).limit == LoginThrottle::Limit::address);
  CHECK(admitted(next(t0 + 1s)));
  CHECK(refused(next(t0 + 1s)).wait == 2s);
  CHECK(admitted(next(t0 + 3s)));
  CHECK(refused(next(t0 + 3s)).wait == 4s);
}

TEST_CASE("attempts are counted when admitted, before any password is checked") {
  // Sent together, none has failed yet when the next is asked about: still only the free ones
  // and the first after them pass, not all 16.
  LoginThrottle throttle;
  int passed = 0;
  for (int i = 0; i < 16; ++i) passed += admitted(throttle.admit("alice", true, "10.0.0.5", t0));
  CHECK(passed == LoginThrottle::kFreeFailures + 1);
}

TEST_CASE("an account gets at most 10 guesses a minute from all addresses together") {
  LoginThrottle throttle;
  int passed = 0;
  for (int i = 0; i < 40; ++i)
    passed += admitted(throttle.admit("alice", true, "10.0.1." + std::to_string(i), t0));
  CHECK(passed == int(LoginThrottle::kGuessesPerWindow));
  const auto answer = refused(throttle.admit("alice", true, "10.0.2.1", t0 + 1s));
  CHECK(answer.limit == LoginThrottle::Limit::account);
  CHECK(answer.wait == 59s);
  CHECK(admitted(throttle.admit("alice", true, "10.0.2.1", t0 + 60s)));
  CHECK(admitted(throttle.admit("bob", true, "10.0.2.2", t0 + 1s)));  // another account
}

TEST_CASE("guesses from addresses that failed leave the owner, from a clean address, room") {
  LoginThrottle throttle;
  // An attacker from two addresses, each failing at once, retrying as fast as it is let.
  int attacker = 0;
  for (auto at = t0; at < t0 + 300s; at += 1s)
    for (const char* address : {"10.6.6.1", "10.6.6.2"})
      attacker += admitted(throttle.admit("alice", true, address, at));
  // Over 5 minutes: at most the suspect share a minute (and the first tries of each address).
  CHECK(attacker <= 2 + 5 * int(LoginThrottle::kSuspectGuessesPerWindow));
  const auto owner = throttle.admit("alice", true, "10.0.0.7", t0 + 300s);
  REQUIRE(admitted(owner));
  throttle.succeeded(std::get<LoginThrottle::Admitted>(owner));
  CHECK(admitted(throttle.admit("alice", true, "10.0.0.7", t0 + 300s)));
}

TEST_CASE("a success clears its address and gives its guess back") {
  LoginThrottle throttle;
  for (int i = 0; i < 3; ++i) CHECK(admitted(throttle.admit("alice", true, "10.0.0.5", t0)));
  const auto right = throttle.admit("alice", true, "10.0.0.5", t0);
  REQUIRE(admitted(right));
  throttle.succeeded(std::get<LoginThrottle::Admitted>(right));
  CHECK(admitted(throttle.admit("alice", true, "10.0.0.5", t0)));  // the address is clean again
  // 4 guesses stand (3 wrong, the right one given back, this one): 6 more from elsewhere pass.
  int passed = 0;
  for (int i = 0; i < 10; ++i)
    passed += admitted(throttle.admit("alice", true, "10.0.3." + std::to_string(i), t0));
  CHECK(passed == 6);
}

TEST_CASE("a flood of made-up names neither grows the tables nor makes an account forget") {
  LoginThrottle throttle;
  for (int i = 0; i < int(LoginThrottle::kGuessesPerWindow); ++i)
    CHECK(admitted(throttle.admit("alice", true, "10.0.4." + std::to_string(i), t0)));
  for (std::size_t i = 0; i < LoginThrottle::kMaxEntries + 100; ++i)
    throttle.admit("u" + std::to_string(i), false, "10.1." + std::to_string(i / 256) + "." +
                   std::to_string(i % 256), t0 + 1s);
  CHECK(refused(throttle.admit("alice", true, "10.0.9.9", t0 + 2s)).limit ==
        LoginThrottle::Limit::account);
}
