// Who may try a console password now (docs/web-console.md, "Logins and guessing"): decided, and
// counted, before the password is hashed, so attempts sent in parallel cannot pass together.
//
// Per address: the first kFreeFailures failures cost nothing (a typing mistake); each one after
// doubles the wait, from 1 s up to kMaxDelay; a success clears it. An attempt counts as a
// failure from the moment it is admitted, until it turns out right.
//
// Per account: at most kGuessesPerWindow guesses in any kGuessWindow, from all addresses
// together. Addresses with failures on record share only kSuspectGuessesPerWindow of them, so an
// attacker guessing from addresses that have failed cannot lock the owner out: the owner,
// from an address with no failures, finds the rest free. A right password gives its guess back.
// An attacker with an endless supply of fresh addresses takes the whole share, as the owner
// would; what it gains is still at most kGuessesPerWindow guesses a window.
//
// Pure: time is passed in. The tables are bounded (kMaxEntries); an account's guesses are never
// forgotten to make room for made-up names.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <string_view>
#include <variant>

namespace tiltgate {

class LoginThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  // One attempt let through to the password check, counted already.
  struct Admitted {
    std::string user, address;
    Clock::time_point at;
  };
  // Why an attempt is refused now, and for how long.
  enum class Limit { address, account };
  struct Refused {
    Limit limit;
    std::chrono::seconds wait;
  };

  // Lets a login by `user` (`is_account`: a name the users file holds) from `address` through
  // to its password check, counting it; or says how long to wait.
  std::variant<Admitted, Refused> admit(std::string_view user, bool is_account,
                                        std::string_view address, Clock::time_point now);
  // The password was right: the address's failures are cleared and the guess is given back.
  void succeeded(const Admitted& attempt);

  static constexpr int kFreeFailures = 3;
  static constexpr std::chrono::seconds kMaxDelay{300};
  static constexpr std::size_t kMaxEntries = 4096;
  static constexpr std::chrono::seconds kGuessWindow{60};
  static constexpr std::size_t kGuessesPerWindow = 10;
  static constexpr std::size_t kSuspectGuessesPerWindow = 5;

 private:
  struct Failures {
    int count = 0;
    Clock::time_point blocked_until;
    Clock::time_point last;
  };
  struct Guesses {
    bool is_account = false;
    std::deque<Clock::time_point> at;  // oldest first, within the window
  };

  void count_failure(std::string_view address, Clock::time_point now);
  Guesses& guesses_of(std::string_view user, bool is_account, Clock::time_point now);

  std::map<std::string, Failures, std::less<>> by_address_;
  std::map<std::string, Guesses, std::less<>> by_user_;
};

}  // namespace tiltgate
