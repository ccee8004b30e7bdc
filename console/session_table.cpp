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

std::string SessionTable::open(std::string user, Role role, std::string credential,
                               Clock::time_point now) {
  std::erase_if(sessions_, [&](const auto& entry) { return expired(entry.second, now); });
  const auto held = std::count_if(sessions_.begin(), sessions_.end(),
                                  [&](const auto& entry) { return entry.second.user == user; });
  if (std::size_t(held) >= kMaxSessionsPerUser) {
    end_least_recent(user);
  } else if (sessions_.size() >= kMaxSessions) {
    end_least_recent({});
  }
  std::string token = random_token();
  sessions_[token] =
      ConsoleSession{std::move(user), role, std::move(credential), random_token(), now, now};
  return token;
}

void SessionTable::end_least_recent(std::string_view user) {
  std::map<std::string_view, std::size_t> held;
  std::size_t most = 0;
  for (const auto& entry : sessions_) most = std::max(most, ++held[entry.second.user]);
  const auto candidate = [&](const ConsoleSession& session) {
    return user.empty() ? held[session.user] == most : session.user == user;
  };
  auto oldest = sessions_.end();
  for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
    if (!candidate(it->second)) continue;
    if (oldest == sessions_.end() || it->second.last_used < oldest->second.last_used) oldest = it;
  }
  if (oldest != sessions_.end()) sessions_.erase(oldest);
}

std::size_t SessionTable::end_changed(const UsersFile* accounts) {
  return std::erase_if(sessions_, [&](const auto& entry) {
    const ConsoleSession& session = entry.second;
    const UserAccount* account = accounts ? accounts->find(session.user) : nullptr;
    return account == nullptr || account->role != session.role ||
           account->hash != session.credential;
  });
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

bool SessionTable::live(std::string_view token, Clock::time_point now) const {
  const auto found = sessions_.find(token);
  return found != sessions_.end() && !expired(found->second, now);
}

void SessionTable::close(std::string_view token) {
  if (const auto found = sessions_.find(token); found != sessions_.end()) sessions_.erase(found);
}

}  // namespace tiltgate
