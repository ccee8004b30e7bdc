// The console's checks of a request that need no state: which session cookie it carries, whether
// it comes from this server's own page, whether a password may be sent over its connection, and
// whether a role may do what a role is needed for. Pure.
#pragma once

#include <string>
#include <string_view>

#include "accounts/role.h"

namespace tiltgate {

inline constexpr std::string_view kSessionCookie = "tiltgate_session";

// The session token in a Cookie header; empty when there is none.
std::string session_token(std::string_view cookie_header);
// Whether an Origin header names this server as the browser reached it (`host` is the Host
// header). No Origin at all (a script, not a browser) passes: the CSRF token still guards it.
bool same_origin(std::string_view origin, std::string_view host, bool https);
// A password may be sent over HTTPS, or over plain HTTP from this machine only.
bool login_allowed(bool https, bool loopback);
// The Set-Cookie value of a new session: Secure unless plain HTTP on loopback, where the browser
// would not send a Secure cookie back.
std::string session_cookie(std::string_view token, bool https, bool loopback);
// Two secrets compared in a time that does not depend on where they differ.
bool same_secret(std::string_view a, std::string_view b);
inline bool role_allows(Role have, Role need) { return int(have) >= int(need); }

}  // namespace tiltgate
