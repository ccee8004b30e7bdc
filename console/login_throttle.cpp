#include "console/login_throttle.h"

#include <algorithm>

namespace tiltgate {

namespace {

std::chrono::seconds delay_after(int failures) {
  const int over = failures - LoginThrottle::kFreeFailures;
  if (over <= 0) return std::chrono::seconds(0);
  if (over > 9) return LoginThrottle::kMaxDelay;
  return std::min(LoginThrottle::kMaxDelay, std::chrono::seconds(1 << (over - 1)));
}

// Rounded up: "wait 0 s" would invite a retry that is still refused.
std::chrono::seconds seconds_until(LoginThrottle::Clock::time_point then,
                                   LoginThrottle::Clock::time_point now) {
  return std::max(std::chrono::seconds(1), std::chrono::ceil<std::chrono::seconds>(then - now));
}

}  // namespace

void LoginThrottle::count_failure(std::string_view address, Clock::time_point now) {
  auto found = by_address_.find(address);
  if (found == by_address_.end()) {
    if (by_address_.size() >= kMaxEntries) {
      by_address_.erase(std::min_element(
          by_address_.begin(), by_address_.end(),
          [](const auto& a, const auto& b) { return a.second.last < b.second.last; }));
    }
    found = by_address_.emplace(std::string(address), Failures{}).first;
  }
  Failures& failures = found->second;
  ++failures.count;
  failures.last = now;
  failures.blocked_until = now + delay_after(failures.count);
}

LoginThrottle::Guesses& LoginThrottle::guesses_of(std::string_view user, bool is_account,
                                                  Clock::time_point now) {
  auto found = by_user_.find(user);
  if (found == by_user_.end()) {
    if (by_user_.size() >= kMaxEntries) {
      // Made-up names make room for each other; an account's guesses stay counted.
      auto oldest = by_user_.end();
      for (auto it = by_user_.begin(); it != by_user_.end(); ++it) {
        if (it->second.is_account) continue;
        const auto last = it->second.at.empty() ? Clock::time_point{} : it->second.at.back();
        if (oldest == by_user_.end() || last < (oldest->second.at.empty()
                                                    ? Clock::time_point{}
                                                    : oldest->second.at.back()))
          oldest = it;
      }
      if (oldest != by_user_.end()) by_user_.erase(oldest);
    }
    found = by_user_.emplace(std::string(user), Guesses{}).first;
  }
  Guesses& guesses = found->second;
  guesses.is_account = is_account;
  while (!guesses.at.empty() && guesses.at.front() + kGuessWindow <= now) guesses.at.pop_front();
  return guesses;
}

std::variant<LoginThrottle::Admitted, LoginThrottle::Refused> LoginThrottle::admit(
    std::string_view user, bool is_account, std::string_view address, Clock::time_point now) {
  const auto failures = by_address_.find(address);
  const bool suspect = failures != by_address_.end() && failures->second.count > 0;
  if (suspect && failures->second.blocked_until > now)
    return Refused{Limit::address, seconds_until(failures->second.blocked_until, now)};
  Guesses& guesses = guesses_of(user, is_account, now);
  const std::size_t share = suspect ? kSuspectGuessesPerWindow : kGuessesPerWindow;
  if (guesses.at.size() >= share) {
    // Free again once all but share - 1 of the window's guesses have left it.
    const auto frees_at = guesses.at[guesses.at.size() - share] + kGuessWindow;
    return Refused{Limit::account, seconds_until(frees_at, now)};
  }
  guesses.at.push_back(now);
  count_failure(address, now);
  return Admitted{std::string(user), std::string(address), now};
}

void LoginThrottle::succeeded(const Admitted& attempt) {
  if (const auto found = by_address_.find(attempt.address); found != by_address_.end())
    by_address_.erase(found);
  if (const auto found = by_user_.find(attempt.user); found != by_user_.end()) {
    auto& at = found->second.at;
    if (const auto mine = std::find(at.begin(), at.end(), attempt.at); mine != at.end())
      at.erase(mine);
  }
}

}  // namespace tiltgate
