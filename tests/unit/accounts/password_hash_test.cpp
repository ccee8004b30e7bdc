// The slow salted hash of console passwords (accounts/password_hash.h): libsodium's argon2id.
#include <doctest/doctest.h>

#include <string>

#include "accounts/password_hash.h"

using namespace tiltgate;

TEST_CASE("a password hash is argon2id with the chosen limits, salted, and verifies its password only") {
  const std::string hash = hash_password("correct horse");
  CHECK(hash.starts_with("$argon2id$v=19$m=19456,t=3,p=1$"));
  CHECK(hash.find("correct horse") == std::string::npos);
  CHECK(verify_password(hash, "correct horse"));
  CHECK_FALSE(verify_password(hash, "correct hors"));
  CHECK_FALSE(verify_password(hash, ""));
  // A fresh salt each time: the same password never gives the same line twice.
  CHECK(hash_password("correct horse") != hash);
}

TEST_CASE("anything but an argon2 hash verifies no password, not even itself") {
  CHECK_FALSE(verify_password("", ""));
  CHECK_FALSE(verify_password("secret", "secret"));
  CHECK_FALSE(verify_password(std::string(300, '$'), ""));
}

TEST_CASE("the hash an unknown user name is checked against has today's limits") {
  // Else an unknown name would answer sooner (or later) than a known one.
  CHECK(hash_has_current_limits(unknown_user_hash()));
  CHECK(hash_has_current_limits(hash_password("x")));
  CHECK_FALSE(hash_has_current_limits(
      "$argon2id$v=19$m=65536,t=2,p=1$1G19JvpNY2Tc+Q2nbJDZyw$O3HHIU2WmfYsF5CWkYWVBv3YzqeyqhkOIRv/KdC2+NI"));
}

TEST_CASE("a hash made with other limits (an older release's) still verifies") {
  // libsodium's INTERACTIVE limits (64 MiB, 2 passes), password "secret".
  CHECK(verify_password(
      "$argon2id$v=19$m=65536,t=2,p=1$1G19JvpNY2Tc+Q2nbJDZyw$O3HHIU2WmfYsF5CWkYWVBv3YzqeyqhkOIRv/KdC2+NI",
      "secret"));
}
