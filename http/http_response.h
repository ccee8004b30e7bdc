// A handler's HttpReply as the HTTP response sent, with the headers every answer carries,
// whatever its route: no caching, no sniffing, no framing, the Content-Security-Policy, no
// Referer sent on, and over HTTPS Strict-Transport-Security
// (docs/web-console.md, "Headers and host names"). And the answer to a request whose Host is not this gateway's.
#pragma once

#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <string_view>

#include "http/host_check.h"
#include "http/http_routes.h"

namespace tiltgate {

// What a page may load and where it may send: only this gateway's own files (the page's script
// and style sheet are files of their own, status/status_page.js and .css: nothing inline) and its
// own API; it may not be framed, nor a form sent elsewhere.
inline constexpr std::string_view kContentSecurityPolicy =
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self'; "
    "connect-src 'self'; form-action 'self'; base-uri 'none'; frame-ancestors 'none'";

boost::beast::http::response<boost::beast::http::string_body> http_response(
    const HttpReply& reply, unsigned version, bool https);

// 400 for a request without a Host header, 421 for one naming another server; the name it gave
// is shown escaped (driver/visible_text.h).
HttpReply misdirected_reply(HostVerdict verdict, std::string_view host);

}  // namespace tiltgate
