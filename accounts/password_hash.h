// The slow salted hash of a console password: libsodium's argon2id, in the encoded form
// "$argon2id$v=19$m=19456,t=3,p=1$SALT$HASH" that carries its own salt and limits, so a hash
// made with other limits (an older release's) still verifies.
// Slow by design (about 25 ms and 19 MiB a call on the development machine, docs/web-console.md):
// never call it on the buses' thread.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tiltgate {

// The limits a new hash is made with: argon2id with 3 passes over 19 MiB (OWASP's memory
// figure for argon2id; libsodium's INTERACTIVE limits take 64 MiB, too much for a small
// gateway serving a few logins at once), one lane.
inline constexpr unsigned long long kPasswordHashPasses = 3;
inline constexpr std::size_t kPasswordHashMemoryBytes = 19456 * 1024;

// The encoded hash of `password` with a fresh random salt; empty when it could not be made
// (libsodium could not start, or the memory above was not there).
std::string hash_password(std::string_view password);
// Whether `password` is the one `hash` was made from. False for anything that is not an
// argon2 hash.
bool verify_password(std::string_view hash, std::string_view password);
// Whether `hash` was made with today's limits (false: a login could store a new one).
bool hash_has_current_limits(std::string_view hash);
// A hash, with today's limits, of a password nobody knows: checked against when a login names
// no account, so that how long the answer takes does not tell which names exist.
std::string_view unknown_user_hash();

}  // namespace tiltgate
