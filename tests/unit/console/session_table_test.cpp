// The console's sessions: a token per login, idle and absolute expiry, logout, the bound, and
// the end of a removed user's sessions.
#include <doctest/doctest.h>

#include "console/session_table.h"

using namespace tiltgate;
using namespace std::chrono_literals;

TEST_CASE("a session is found by its token and carries the user, role and a CSRF token") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string token = table.open("alice", Role::operator_, t0);
  CHECK(token.size() == 64);
  const ConsoleSession* session = table.use(token, t0 + 1s);
  REQUIRE(session != nullptr);
  CHECK(session->user == "alice");
  CHECK(session->role == Role::operator_);
  CHECK(session->csrf.size() == 64);
  CHECK(session->csrf != token);
  CHECK(table.use("not-a-token", t0) == nullptr);
  CHECK(table.open("alice", Role::operator_, t0) != token);  // each login a new token
}

TEST_CASE("a session ends after the idle time without use, and at its absolute age whatever") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string idle = table.open("alice", Role::viewer, t0);
  CHECK(table.use(idle, t0 + 899s) != nullptr);
  CHECK(table.use(idle, t0 + 899s + 899s) != nullptr);  // each use restarts the idle time
  CHECK(table.use(idle, t0 + 899s + 899s + 900s) == nullptr);
  CHECK(table.use(idle, t0 + 10s) == nullptr);  // gone for good

  const std::string busy = table.open("bob", Role::admin, t0);
  for (auto t = t0; t < t0 + 3600s; t += 600s) CHECK(table.use(busy, t) != nullptr);
  CHECK(table.use(busy, t0 + 3600s) == nullptr);
}

TEST_CASE("logout ends the session, and a removed or re-roled user's sessions end") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string a = table.open("alice", Role::admin, t0);
  const std::string b = table.open("bob", Role::operator_, t0);
  const std::string c = table.open("carol", Role::viewer, t0);
  table.close(a);
  CHECK(table.use(a, t0) == nullptr);
  table.keep_only([](const std::string& user) -> std::optional<Role> {
    if (user == "bob") return Role::viewer;  // demoted: logs in again
    if (user == "carol") return Role::viewer;
    return std::nullopt;
  });
  CHECK(table.use(b, t0) == nullptr);
  CHECK(table.use(c, t0) != nullptr);
}

TEST_CASE("the table is bounded: the least recently used session goes first") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string first = table.open("u0", Role::viewer, t0);
  const std::string second = table.open("u1", Role::viewer, t0 + 1s);
  CHECK(table.use(first, t0 + 2s) != nullptr);  // now second is the least recently used
  for (std::size_t i = 2; i < SessionTable::kMaxSessions + 1; ++i)
    table.open("u" + std::to_string(i), Role::viewer, t0 + 3s);
  CHECK(table.size() == SessionTable::kMaxSessions);
  CHECK(table.use(second, t0 + 4s) == nullptr);
  CHECK(table.use(first, t0 + 4s) != nullptr);
}
