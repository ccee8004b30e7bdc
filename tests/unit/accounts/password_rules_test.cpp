// What a new console password must be (accounts/password_rules.h; issue 52, item 8): at least
// 10 characters, not the account's name, not one of the most common passwords.
#include <doctest/doctest.h>

#include "accounts/password_rules.h"

using tiltgate::password_weakness;

TEST_CASE("a password of fewer than 10 characters is refused, saying how many it needs") {
  CHECK(password_weakness("alice", "x") == "a password needs at least 10 characters");
  CHECK(password_weakness("alice", "Tr0ub4dor") == "a password needs at least 10 characters");
  CHECK_FALSE(password_weakness("alice", "Tr0ub4dor&").has_value());
}

TEST_CASE("the characters of a password are counted, not its bytes") {
  // Nine characters, 18 bytes in UTF-8.
  CHECK(password_weakness("alice", "ääääääääää").has_value() == false);
  CHECK(password_weakness("alice", "äääääääää").has_value());
}

TEST_CASE("a password that is the account's name is refused, whatever its case") {
  CHECK(password_weakness("nightshift", "nightshift") == "the password is the account's name");
  CHECK(password_weakness("nightshift", "NightShift") == "the password is the account's name");
  CHECK_FALSE(password_weakness("nightshift", "nightshift-7rQ").has_value());
}

TEST_CASE("one of the most common passwords is refused, whatever its case") {
  for (const char* common : {"1234567890", "password123", "QWERTYUIOP", "administrator"})
    CHECK(password_weakness("alice", common) == "the password is one of the most common ones");
  CHECK_FALSE(password_weakness("alice", "correct horse battery").has_value());
}
