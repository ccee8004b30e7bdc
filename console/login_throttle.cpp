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

}  // namespace

void LoginThrottle::count(Table& table, std::string_view key, Clock::time_point now) {
  auto found = table.find(key);
  if (found == table.end()) {
    if (table.size() >= kMaxEntries) {
      table.erase(std::min_element(table.begin(), table.end(), [](const auto& a, const auto& b) {
        return a.second.last < b.second.last;
      }));
    }
    found = table.emplace(std::string(key), Failures{}).first;
  }
  Failures& failures = found->second;
  ++failures.count;
  failures.last = now;
  failures.blocked_until = now + delay_after(failures.count);
}

std::optional<std::chrono::seconds> LoginThrottle::remaining(const Table& table,
                                                             std::string_view key,
                                                             Clock::time_point now) {
  const auto found = table.find(key);
  if (found == table.end() || found->second.blocked_until <= now) return std::nullopt;
  const auto left = found->second.blocked_until - now;
  // Rounded up: "wait 0 s" would invite a retry that is still refused.
  return std::chrono::ceil<std::chrono::seconds>(left);
}

std::optional<std::chrono::seconds> LoginThrottle::wait(std::string_view user,
                                                        std::string_view address,
                                                        Clock::time_point now) const {
  const auto a = remaining(by_user_, user, now);
  const auto b = remaining(by_address_, address, now);
  if (a && b) return std::max(*a, *b);
  return a ? a : b;
}

void LoginThrottle::failed(std::string_view user, std::string_view address,
                           Clock::time_point now) {
  count(by_user_, user, now);
  count(by_address_, address, now);
}

void LoginThrottle::succeeded(std::string_view user, std::string_view address) {
  if (const auto found = by_user_.find(user); found != by_user_.end()) by_user_.erase(found);
  if (const auto found = by_address_.find(address); found != by_address_.end())
    by_address_.erase(found);
}

}  // namespace tiltgate
