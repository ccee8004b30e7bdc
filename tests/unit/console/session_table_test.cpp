// The console's sessions: a token per login, idle and absolute expiry, logout, the bound, and
// the end of the sessions of an account removed, given another role or a new password.
#include <doctest/doctest.h>

#include <fmt/format.h>

#include "console/session_table.h"

using namespace tiltgate;
using namespace std::chrono_literals;

TEST_CASE("a session is found by its token and carries the user, role and a CSRF token") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string token = table.open("alice", Role::operator_, "h", t0);
  CHECK(token.size() == 64);
  const ConsoleSession* session = table.use(token, t0 + 1s);
  REQUIRE(session != nullptr);
  CHECK(session->user == "alice");
  CHECK(session->role == Role::operator_);
  CHECK(session->csrf.size() == 64);
  CHECK(session->csrf != token);
  CHECK(table.use("not-a-token", t0) == nullptr);
  CHECK(table.open("alice", Role::operator_, "h", t0) != token);  // each login a new token
}

TEST_CASE("a session ends after the idle time without use, and at its absolute age whatever") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string idle = table.open("alice", Role::viewer, "h", t0);
  CHECK(table.use(idle, t0 + 899s) != nullptr);
  CHECK(table.use(idle, t0 + 899s + 899s) != nullptr);  // each use restarts the idle time
  CHECK(table.use(idle, t0 + 899s + 899s + 900s) == nullptr);
  CHECK(table.use(idle, t0 + 10s) == nullptr);  // gone for good

  const std::string busy = table.open("bob", Role::admin, "h", t0);
  for (auto t = t0; t < t0 + 3600s; t += 600s) CHECK(table.use(busy, t) != nullptr);
  CHECK(table.use(busy, t0 + 3600s) == nullptr);
}

namespace {

// Accounts as the users file holds them; the hashes are made up (no password is checked here).
UsersFile accounts(std::string_view text) {
  auto file = UsersFile::parse(text, "users");
  REQUIRE(file.skipped().empty());
  return file;
}

constexpr std::string_view kHashA = "$argon2id$v=19$m=19456,t=3,p=1$AAAA$aaaa";
constexpr std::string_view kHashB = "$argon2id$v=19$m=19456,t=3,p=1$BBBB$bbbb";

}  // namespace

TEST_CASE("logout ends the session") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string a = table.open("alice", Role::admin, "h", t0);
  table.close(a);
  CHECK(table.use(a, t0) == nullptr);
}

TEST_CASE("a session ends when its account is removed, given another role or a new password") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string kept = table.open("keep", Role::admin, std::string(kHashA), t0);
  const std::string removed = table.open("gone", Role::admin, std::string(kHashA), t0);
  const std::string demoted = table.open("demoted", Role::admin, std::string(kHashA), t0);
  const std::string promoted = table.open("promoted", Role::viewer, std::string(kHashA), t0);
  const std::string repassworded = table.open("newpass", Role::operator_, std::string(kHashA), t0);
  const UsersFile now = accounts(fmt::format(
      "keep:admin:{0}\ndemoted:viewer:{0}\npromoted:admin:{0}\nnewpass:operator:{1}\n", kHashA,
      kHashB));
  CHECK(table.end_changed(&now) == 4);
  CHECK(table.use(kept, t0) != nullptr);
  CHECK(table.use(removed, t0) == nullptr);
  CHECK(table.use(demoted, t0) == nullptr);
  CHECK(table.use(promoted, t0) == nullptr);
  CHECK(table.use(repassworded, t0) == nullptr);
  CHECK(table.end_changed(&now) == 0);  // what stays is as it was
}

TEST_CASE("every session ends when there are no accounts to hold them to (an unreadable file)") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string a = table.open("alice", Role::admin, std::string(kHashA), t0);
  CHECK(table.end_changed(nullptr) == 1);
  CHECK(table.use(a, t0) == nullptr);
}

TEST_CASE("the table is bounded: the least recently used session goes first") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string first = table.open("u0", Role::viewer, "h", t0);
  const std::string second = table.open("u1", Role::viewer, "h", t0 + 1s);
  CHECK(table.use(first, t0 + 2s) != nullptr);  // now second is the least recently used
  for (std::size_t i = 2; i < SessionTable::kMaxSessions + 1; ++i)
    table.open("u" + std::to_string(i), Role::viewer, "h", t0 + 3s);
  CHECK(table.size() == SessionTable::kMaxSessions);
  CHECK(table.use(second, t0 + 4s) == nullptr);
  CHECK(table.use(first, t0 + 4s) != nullptr);
}

TEST_CASE("one user logging in again and again pushes out only their own sessions") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string admin = table.open("admin", Role::admin, "h", t0);
  std::string first_viewer = table.open("viewer", Role::viewer, "h", t0 + 1s);
  for (int i = 0; i < 260; ++i) table.open("viewer", Role::viewer, "h", t0 + 2s);
  CHECK(table.use(admin, t0 + 3s) != nullptr);
  CHECK(table.use(first_viewer, t0 + 3s) == nullptr);  // the viewer's own oldest went
  CHECK(table.size() == 1 + SessionTable::kMaxSessionsPerUser);
}

TEST_CASE("a full table takes the room from the user holding the most sessions") {
  SessionTable table(900s, 3600s);
  const auto t0 = SessionTable::Clock::time_point{} + 1000s;
  const std::string admin = table.open("admin", Role::admin, "h", t0);  // the oldest
  std::size_t opened = 1;
  for (int user = 0; opened < SessionTable::kMaxSessions; ++user)
    for (std::size_t i = 0; i < SessionTable::kMaxSessionsPerUser - (user == 0 ? 0 : 1) &&
                            opened < SessionTable::kMaxSessions;
         ++i, ++opened)
      table.open("u" + std::to_string(user), Role::viewer, "h", t0 + 1s);
  REQUIRE(table.size() == SessionTable::kMaxSessions);
  table.open("newcomer", Role::viewer, "h", t0 + 2s);
  CHECK(table.size() == SessionTable::kMaxSessions);
  CHECK(table.use(admin, t0 + 3s) != nullptr);  // least recently used, but holding only one
}
