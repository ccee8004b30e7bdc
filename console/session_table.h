// The web console's logged-in sessions: a random token (the cookie) per login, with the user,
// their role and the CSRF token the page sends back on every change. A session ends after
// [http] session_idle_seconds without a request, session_max_seconds after its login, at
// logout, or when its user's account is removed or its role changed. Pure: time is passed in.
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "accounts/role.h"

namespace tiltgate {

struct ConsoleSession {
  std::string user;
  Role role = Role::viewer;
  std::string csrf;
  std::chrono::steady_clock::time_point created, last_used;
};

class SessionTable {
 public:
  using Clock = std::chrono::steady_clock;
  SessionTable(std::chrono::seconds idle, std::chrono::seconds max) : idle_(idle), max_(max) {}

  // A new session for `user`; returns its token. At kMaxSessions the least recently used one
  // goes, so a flood of logins cannot grow the table.
  std::string open(std::string user, Role role, Clock::time_point now);
  // The live session of `token`, its last use now; none when unknown or expired (then gone).
  const ConsoleSession* use(std::string_view token, Clock::time_point now);
  void close(std::string_view token);
  // Ends the sessions of users no longer there, or whose role changed (`role_of` says: none
  // when the account is gone).
  template <class RoleOf>
  void keep_only(RoleOf role_of) {
    std::erase_if(sessions_, [&](const auto& entry) {
      const auto role = role_of(entry.second.user);
      return !role || *role != entry.second.role;
    });
  }
  std::size_t size() const { return sessions_.size(); }
  // A reload's new [http] session keys, from now on (for the sessions open too).
  void set_limits(std::chrono::seconds idle, std::chrono::seconds max) {
    idle_ = idle;
    max_ = max;
  }

  static constexpr std::size_t kMaxSessions = 256;

 private:
  bool expired(const ConsoleSession& session, Clock::time_point now) const;

  std::chrono::seconds idle_, max_;
  std::map<std::string, ConsoleSession, std::less<>> sessions_;
};

// 32 random bytes from OpenSSL's generator, in hex: a session or CSRF token.
std::string random_token();

}  // namespace tiltgate
