#include "http/http_request.h"

#include <boost/asio/ip/address.hpp>
#include <boost/beast/http/error.hpp>
#include <utility>

namespace tiltgate {

namespace http = boost::beast::http;

std::string header_of(const BeastRequest& request, http::field field) {
  const auto found = request.find(field);
  if (found == request.end()) return {};
  return std::string(found->value());
}

std::string header_of(const BeastRequest& request, std::string_view name) {
  const auto found = request.find(boost::beast::string_view(name.data(), name.size()));
  if (found == request.end()) return {};
  return std::string(found->value());
}

boost::system::error_code limit_body(http::request_parser<http::string_body>& parser,
                                     std::size_t limit) {
  if (const auto length = parser.content_length(); length && *length > limit)
    return http::error::body_limit;
  parser.body_limit(limit);
  return {};
}

bool is_loopback_address(const std::string& address) {
  boost::system::error_code ec;
  const auto parsed = boost::asio::ip::make_address(address, ec);
  return !ec && parsed.is_loopback();
}

HttpRequest http_request_of(BeastRequest& request, const std::string& address, bool https) {
  HttpRequest asked;
  asked.method = std::string(request.method_string());
  asked.target = std::string(request.target());
  asked.cookie = header_of(request, http::field::cookie);
  asked.csrf_token = header_of(request, "X-CSRF-Token");
  asked.origin = header_of(request, http::field::origin);
  asked.host = header_of(request, http::field::host);
  asked.content_type = header_of(request, http::field::content_type);
  asked.address = address;
  asked.https = https;
  asked.loopback = is_loopback_address(address);
  asked.body = std::move(request.body());
  return asked;
}

}  // namespace tiltgate
