// A request Beast reads: its body held to a limit, and the request as the handler takes it
// (HttpRequest, http/http_routes.h): its method, target, the headers the routes ask for, its
// body, and where it came from. Pure: no socket.
#pragma once

#include <boost/beast/http/message.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/string_body.hpp>
#include <string>
#include <string_view>

#include "http/http_routes.h"

namespace tiltgate {

using BeastRequest = boost::beast::http::request<boost::beast::http::string_body>;

// A header's value; empty when the request has none.
std::string header_of(const BeastRequest& request, boost::beast::http::field field);
std::string header_of(const BeastRequest& request, std::string_view name);

// Holds the body of the request whose header `parser` has read to `limit`: one that says it is
// longer is refused at once (Beast checks a Content-Length against the limit only at the end of
// the header), a chunked one as its chunks come.
boost::system::error_code limit_body(
    boost::beast::http::request_parser<boost::beast::http::string_body>& parser, std::size_t limit);

// Whether `address` (without a port) is a loopback address; false when it is none.
bool is_loopback_address(const std::string& address);

// The request from `address` (the client's, without its port); its body is moved out.
HttpRequest http_request_of(BeastRequest& request, const std::string& address, bool https);

}  // namespace tiltgate
