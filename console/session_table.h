// The web console's logged-in sessions: a random token (the cookie) per login, with the user,
// their role, their account's password hash at the login and the CSRF token the page sends
// back on every change. A session ends after [http] session_idle_seconds without a request,
// session_max_seconds after its login, at logout, or when its user's account is removed, its
// role changed or its password set anew (docs/web-console.md, "When a session ends"). The table
// is bounded and fair per user: one user's logins only ever push out that user's own sessions,
// unless the table is full, and then the user holding the most gives way. Pure: time is passed
// in.
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "accounts/role.h"
#include "accounts/users_file.h"

namespace tiltgate {

struct ConsoleSession {
  std::string user;
  Role role = Role::viewer;
  // The account's hash when the session began: another one in the users file means a new
  // password, which ends the session.
  std::string credential;
  std::string csrf;
  std::chrono::steady_clock::time_point created, last_used;
};

class SessionTable {
 public:
  using Clock = std::chrono::steady_clock;
  SessionTable(std::chrono::seconds idle, std::chrono::seconds max) : idle_(idle), max_(max) {}

  // A new session for `user`, whose account's hash is `credential`; returns its token. A user
  // holding kMaxSessionsPerUser loses their own least recently used one; a table holding
  // kMaxSessions loses the least recently used one of the user holding the most. So a flood
  // of logins cannot grow the table, and one account's logins cannot log the others out.
  std::string open(std::string user, Role role, std::string credential, Clock::time_point now);
  // The live session of `token`, its last use now; none when unknown or expired (then gone).
  const ConsoleSession* use(std::string_view token, Clock::time_point now);
  // Whether `token` is a live session, without using it.
  bool live(std::string_view token, Clock::time_point now) const;
  void close(std::string_view token);
  // Ends the sessions whose account `accounts` no longer holds as it was at their login (gone,
  // another role, another password); every session when there are no accounts (an unreadable
  // file). Returns how many ended.
  std::size_t end_changed(const UsersFile* accounts);
  std::size_t size() const { return sessions_.size(); }
  // A reload's new [http] session keys, from now on (for the sessions open too).
  void set_limits(std::chrono::seconds idle, std::chrono::seconds max) {
    idle_ = idle;
    max_ = max;
  }

  static constexpr std::size_t kMaxSessions = 256;
  // A person's browsers and tabs with room to spare; a script that logs in at every call
  // pushes out its own sessions, nobody else's.
  static constexpr std::size_t kMaxSessionsPerUser = 16;

 private:
  bool expired(const ConsoleSession& session, Clock::time_point now) const;
  // Ends the least recently used session of `user`, or of the user holding the most when empty.
  void end_least_recent(std::string_view user);

  std::chrono::seconds idle_, max_;
  std::map<std::string, ConsoleSession, std::less<>> sessions_;
};

// 32 random bytes from OpenSSL's generator, in hex: a session or CSRF token.
std::string random_token();

}  // namespace tiltgate
