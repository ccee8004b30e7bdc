#include "accounts/password_hash.h"

#include <sodium.h>

namespace tiltgate {

namespace {

// sodium_init() is safe to call from any thread, any number of times (it returns 1 once done).
bool sodium_ready() { return sodium_init() >= 0; }

}  // namespace

std::string hash_password(std::string_view password) {
  if (!sodium_ready()) return {};
  char hash[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str(hash, password.data(), password.size(), kPasswordHashPasses,
                        kPasswordHashMemoryBytes) != 0)
    return {};
  return hash;
}

bool verify_password(std::string_view hash, std::string_view password) {
  // libsodium reads a NUL-terminated string of at most crypto_pwhash_STRBYTES - 1 characters.
  if (!sodium_ready() || hash.size() >= crypto_pwhash_STRBYTES) return false;
  const std::string terminated(hash);
  return crypto_pwhash_str_verify(terminated.c_str(), password.data(), password.size()) == 0;
}

bool hash_has_current_limits(std::string_view hash) {
  if (!sodium_ready() || hash.size() >= crypto_pwhash_STRBYTES) return false;
  const std::string terminated(hash);
  return crypto_pwhash_str_needs_rehash(terminated.c_str(), kPasswordHashPasses,
                                        kPasswordHashMemoryBytes) == 0;
}

std::string_view unknown_user_hash() {
  // Made once by hash_password() of a random password that was then thrown away. A unit test
  // checks its limits are kPasswordHash*'s: change them, and make this again.
  return "$argon2id$v=19$m=19456,t=3,p=1$BDKsJoVMct6NfHxHnSrb6A$"
         "F+4ckCt+viMFhnJTTU6+C2n6H+Xw6wU7Mfjgq333NU0";
}

}  // namespace tiltgate
