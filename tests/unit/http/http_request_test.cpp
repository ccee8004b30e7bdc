// A request Beast read, as the handler takes it (http/http_request.h): its headers and body,
// where it came from, and an anonymous body held to its limit from its Content-Length.
#include <doctest/doctest.h>

#include <boost/asio/buffer.hpp>
#include <boost/beast/http/error.hpp>
#include <string>

#include "http/http_request.h"

using namespace tiltgate;
namespace http = boost::beast::http;

namespace {

// `header` fed to a fresh parser, which stops at the end of the header.
boost::system::error_code parse_header(http::request_parser<http::string_body>& parser,
                                       const std::string& header) {
  boost::system::error_code ec;
  parser.eager(false);
  parser.put(boost::asio::buffer(header), ec);
  return ec;
}

}  // namespace

TEST_CASE("a request as the handler takes it: method, target, headers, body and its client") {
  BeastRequest request{http::verb::post, "/api/sensors/a%20b/settings", 11};
  request.set(http::field::cookie, "session=abc");
  request.set("X-CSRF-Token", "token");
  request.set(http::field::origin, "https://gw.example");
  request.set(http::field::host, "gw.example:8443");
  request.set(http::field::content_type, "application/json");
  request.body() = R"({"value": 3})";
  const HttpRequest asked = http_request_of(request, "127.0.0.1", true);
  CHECK(asked.method == "POST");
  CHECK(asked.target == "/api/sensors/a%20b/settings");
  CHECK(asked.cookie == "session=abc");
  CHECK(asked.csrf_token == "token");
  CHECK(asked.origin == "https://gw.example");
  CHECK(asked.host == "gw.example:8443");
  CHECK(asked.content_type == "application/json");
  CHECK(asked.body == R"({"value": 3})");
  CHECK(asked.address == "127.0.0.1");
  CHECK(asked.https);
  CHECK(asked.loopback);
}

TEST_CASE("headers a request lacks are empty, and only a loopback address is loopback") {
  BeastRequest request{http::verb::get, "/", 11};
  const HttpRequest asked = http_request_of(request, "192.0.2.7", false);
  CHECK(asked.cookie.empty());
  CHECK(asked.csrf_token.empty());
  CHECK(asked.origin.empty());
  CHECK(asked.host.empty());
  CHECK_FALSE(asked.https);
  CHECK_FALSE(asked.loopback);
  CHECK(is_loopback_address("::1"));
  CHECK(is_loopback_address("127.0.0.5"));
  CHECK_FALSE(is_loopback_address("10.0.0.1"));
  CHECK_FALSE(is_loopback_address("not an address"));
}

TEST_CASE("a body longer than the limit is refused from its Content-Length, before it is read") {
  http::request_parser<http::string_body> too_long;
  REQUIRE_FALSE(parse_header(too_long, "POST /login HTTP/1.1\r\nHost: gw\r\n"
                                       "Content-Length: 5000\r\n\r\n"));
  CHECK(limit_body(too_long, 4096) == http::error::body_limit);
  http::request_parser<http::string_body> short_enough;
  REQUIRE_FALSE(parse_header(short_enough, "POST /login HTTP/1.1\r\nHost: gw\r\n"
                                           "Content-Length: 100\r\n\r\n"));
  CHECK_FALSE(limit_body(short_enough, 4096));
}
