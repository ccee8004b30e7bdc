#include "console/request_guard.h"

#include <openssl/crypto.h>

#include <fmt/format.h>

namespace tiltgate {

std::string session_token(std::string_view header) {
  while (!header.empty()) {
    const auto end = header.find(';');
    std::string_view part = header.substr(0, end);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.starts_with(kSessionCookie) && part.size() > kSessionCookie.size() &&
        part[kSessionCookie.size()] == '=')
      return std::string(part.substr(kSessionCookie.size() + 1));
    if (end == std::string_view::npos) break;
    header = header.substr(end + 1);
  }
  return {};
}

bool same_origin(std::string_view origin, std::string_view host, bool https) {
  if (origin.empty()) return true;
  return origin == fmt::format("{}://{}", https ? "https" : "http", host);
}

bool login_allowed(bool https, bool loopback) { return https || loopback; }

std::string session_cookie(std::string_view token, bool https, bool loopback) {
  const bool secure = https || !loopback;
  return fmt::format("{}={}; HttpOnly;{} SameSite=Strict; Path=/", kSessionCookie, token,
                     secure ? " Secure;" : "");
}

bool same_secret(std::string_view a, std::string_view b) {
  return a.size() == b.size() && !a.empty() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace tiltgate
