// Growing delays after failed console logins, counted per account and per client address, so
// that guessing passwords is slow whether one account is tried from many places or many
// accounts from one. The first kFreeFailures failures cost nothing (a typing mistake); each one
// after doubles the wait, from 1 s up to kMaxDelay. A success clears the account's and the
// address's count. Pure: time is passed in. Both tables are bounded (the oldest entry goes), so
// a flood of made-up names cannot grow them.
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace tiltgate {

class LoginThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  // How long `user` from `address` must still wait before a login is tried; none: now.
  std::optional<std::chrono::seconds> wait(std::string_view user, std::string_view address,
                                           Clock::time_point now) const;
  void failed(std::string_view user, std::string_view address, Clock::time_point now);
  void succeeded(std::string_view user, std::string_view address);

  static constexpr int kFreeFailures = 3;
  static constexpr std::chrono::seconds kMaxDelay{300};
  static constexpr std::size_t kMaxEntries = 4096;

 private:
  struct Failures {
    int count = 0;
    Clock::time_point blocked_until;
    Clock::time_point last;
  };
  using Table = std::map<std::string, Failures, std::less<>>;
  static void count(Table& table, std::string_view key, Clock::time_point now);
  static std::optional<std::chrono::seconds> remaining(const Table& table, std::string_view key,
                                                       Clock::time_point now);

  Table by_user_, by_address_;
};

}  // namespace tiltgate
