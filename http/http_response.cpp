#include "http/http_response.h"

#include <fmt/format.h>

#include "driver/visible_text.h"

namespace tiltgate {

namespace http = boost::beast::http;

http::response<http::string_body> http_response(const HttpReply& reply, unsigned version,
                                                bool https) {
  http::response<http::string_body> response{http::status(reply.status), version};
  response.set(http::field::server, "tiltgate");
  response.set(http::field::content_type, reply.content_type);
  response.set(http::field::cache_control, "no-store");
  if (reply.allow_get) response.set(http::field::allow, "GET, HEAD");
  if (!reply.content_disposition.empty())
    response.set(http::field::content_disposition, reply.content_disposition);
  for (const auto& [name, value] : reply.headers) response.insert(name, value);
  if (https) response.set(http::field::strict_transport_security, "max-age=31536000");
  response.set("X-Content-Type-Options", "nosniff");
  response.set("X-Frame-Options", "DENY");
  response.set("Content-Security-Policy", boost::beast::string_view(kContentSecurityPolicy.data(),
                                                                  kContentSecurityPolicy.size()));
  response.set("Referrer-Policy", "no-referrer");
  response.body() = reply.body;
  return response;
}

HttpReply misdirected_reply(HostVerdict verdict, std::string_view host) {
  if (verdict == HostVerdict::missing)
    return HttpReply{400, "text/plain; charset=utf-8",
                     "a Host header naming this gateway is required\n"};
  return HttpReply{421, "text/plain; charset=utf-8",
                   fmt::format("this gateway does not answer to the name \"{}\": use one of its "
                               "[http] server_names, or add this name there\n",
                               visible_text(host))};
}

}  // namespace tiltgate
