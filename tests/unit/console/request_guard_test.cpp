// The console's stateless checks: the session cookie, the same-origin rule, where a password
// may be sent, the cookie's flags, and the role order.
#include <doctest/doctest.h>

#include "console/request_guard.h"

using namespace tiltgate;

TEST_CASE("the session token is taken from the Cookie header, among other cookies") {
  CHECK(session_token("tiltgate_session=abc123") == "abc123");
  CHECK(session_token("theme=dark; tiltgate_session=abc123; lang=de") == "abc123");
  CHECK(session_token("tiltgate_sessionx=abc; other=1").empty());
  CHECK(session_token("").empty());
}

TEST_CASE("a change is accepted from this server's own page, or from a client that sends no Origin") {
  CHECK(same_origin("http://127.0.0.1:8080", "127.0.0.1:8080", false));
  CHECK(same_origin("https://gw.plant:8443", "gw.plant:8443", true));
  CHECK(same_origin("", "gw.plant:8443", true));
  CHECK_FALSE(same_origin("https://evil.example", "gw.plant:8443", true));
  CHECK_FALSE(same_origin("http://gw.plant:8443", "gw.plant:8443", true));  // scheme matters
  CHECK_FALSE(same_origin("null", "gw.plant:8443", true));
}

TEST_CASE("a password goes over HTTPS, or over plain HTTP from this machine only") {
  CHECK(login_allowed(true, false));
  CHECK(login_allowed(true, true));
  CHECK(login_allowed(false, true));
  CHECK_FALSE(login_allowed(false, false));
}

TEST_CASE("the session cookie is HttpOnly and SameSite=Strict, Secure but on a plain loopback console") {
  CHECK(session_cookie("t", true, false) == "tiltgate_session=t; HttpOnly; Secure; SameSite=Strict; Path=/");
  CHECK(session_cookie("t", true, true) == "tiltgate_session=t; HttpOnly; Secure; SameSite=Strict; Path=/");
  CHECK(session_cookie("t", false, true) == "tiltgate_session=t; HttpOnly; SameSite=Strict; Path=/");
}

TEST_CASE("secrets compare equal only when whole and equal, and roles are ordered") {
  CHECK(same_secret("abcd", "abcd"));
  CHECK_FALSE(same_secret("abcd", "abce"));
  CHECK_FALSE(same_secret("abc", "abcd"));
  CHECK_FALSE(same_secret("", ""));  // no token is never a match
  CHECK(role_allows(Role::admin, Role::operator_));
  CHECK(role_allows(Role::operator_, Role::operator_));
  CHECK_FALSE(role_allows(Role::viewer, Role::operator_));
  CHECK_FALSE(role_allows(Role::operator_, Role::admin));
}
