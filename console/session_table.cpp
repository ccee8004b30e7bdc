#include "console/session_table.h"

#include <openssl/rand.h>

#include <algorithm>
#include <stdexcept>

namespace tiltgate {

std::string random_token() {
  unsigned char bytes[32];
  if (RAND_bytes(bytes, sizeof bytes) != 1)
    throw std::runtime_error("no random bytes for a session token");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string token;
  for (unsigned char b : bytes) {
    token += kHex[b >> 4];
    token += kHex[b & 15];
  }
  return token;
}

bool SessionTable::expired(const ConsoleSession& session, Clock::time_point now) const {
  return now - session.last_used >= idle_ || now - session.created >= max_;
}

std::string SessionTable::open(std::string user, Role role, Clock::time_point now) {
  std::erase_if(sessions_, [&](const auto& entry) { return expired(entry.second, now); });
  if (sessions_.size() >= kMaxSessions) {
    const auto oldest = std::min_element(
        sessions_.begin(), sessions_.end(),
        [](const auto& a, const auto& b) { return a.second.last_used < b.second.last_used; });
    sessions_.erase(oldest);
  }
  std::string token = random_token();
  sessions_[token] = ConsoleSession{std::move(user), role, random_token(), now, now};
  return token;
}

const ConsoleSession* SessionTable::use(std::string_view token, Clock::time_point now) {
  const auto found = sessions_.find(token);
  if (found == sessions_.end()) return nullptr;
  if (expired(found->second, now)) {
    sessions_.erase(found);
    return nullptr;
  }
  found->second.last_used = now;
  return &found->second;
}

void SessionTable::close(std::string_view token) {
  if (const auto found = sessions_.find(token); found != sessions_.end()) sessions_.erase(found);
}

}  // namespace tiltgate
