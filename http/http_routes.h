// What each HTTP request is answered with (docs/northbound.md, "HTTP status API and metrics"). Pure: the
// server (http/http_server.h) hands it the method and target, and a way to take the
// gateway's status, which is taken only for the endpoints that show it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "status/angle_history.h"
#include "gateway/gateway_status.h"

namespace tiltgate {

struct HttpReply {
  unsigned status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
  bool allow_get = false;  // 405: the reply names GET as the one method allowed
  std::string content_disposition{};  // e.g. a download's file name; empty: no such header
  std::vector<std::pair<std::string, std::string>> headers{};  // more: Set-Cookie, Retry-After
};

// One request as the handler sees it: what the server read, and where it came from.
struct HttpRequest {
  std::string method;
  std::string target;
  std::string body;
  std::string cookie;        // the Cookie header
  std::string csrf_token;    // X-CSRF-Token
  std::string origin;        // Origin; empty when the client sent none
  std::string host;          // Host
  std::string content_type;
  std::string address;       // the client's address without its port
  bool https = false;        // it came over TLS
  bool loopback = false;     // from this machine
};

// A sensor's recent angles, oldest first; none for a name not configured.
using HistorySource = std::function<std::optional<std::vector<AngleSample>>(std::string_view)>;

// %XX escapes decoded, so a sensor name may be asked for as a browser writes it. None when
// an escape is malformed.
std::optional<std::string> percent_decoded(std::string_view path);
// A sensor's or bus's name from a path segment, %XX decoded; none when malformed or holding '/'.
std::optional<std::string> path_name(std::string_view text);
// A query parameter's value, '+' and %XX decoded; empty when absent or malformed.
std::string query_value(std::string_view target, std::string_view name);

// GET (and HEAD) only: nothing can be changed over HTTP. The query string is ignored. Without
// a history source every sensor's history is empty.
HttpReply route_http(std::string_view method, std::string_view target, const StatusSource& status,
                     const HistorySource& history = {});

}  // namespace tiltgate
