#include "modbus_tcp/tcp_listen.h"
#include "status/http_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using asio::ip::tcp;

namespace {

constexpr auto accept_retry_pause = std::chrono::milliseconds(100);

}  // namespace

struct HttpServer::Connection {
  explicit Connection(tcp::socket socket) : stream(std::move(socket)) {}
  void close() {
    boost::system::error_code ec;
    stream.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream.socket().close(ec);
  }
  beast::tcp_stream stream;
};

HttpServer::HttpServer(asio::any_io_executor executor, StatusSource status,
                       HttpServerOptions options, HistorySource history)
    : executor_(executor),
      status_(std::move(status)),
      options_(std::move(options)),
      history_(std::move(history)),
      acceptor_(executor) {}

HttpServer::~HttpServer() = default;

Expected<Done, std::string> HttpServer::start() {
  if (acceptor_.is_open()) return Unexpected{std::string("HTTP server already started")};
  if (auto listening = listen_on(acceptor_, options_.listen, options_.port, "HTTP"); !listening)
    return listening;
  asio::co_spawn(executor_, accept_clients(), asio::detached);
  return Done{};
}

std::uint16_t HttpServer::local_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

void HttpServer::stop() {
  boost::system::error_code ec;
  acceptor_.close(ec);
  for (const auto& connection : connections_) connection->close();
}

asio::awaitable<void> HttpServer::accept_clients() {
  while (acceptor_.is_open()) {
    boost::system::error_code ec;
    tcp::socket socket =
        co_await acceptor_.async_accept(asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      if (!acceptor_.is_open()) co_return;
      // Out of descriptors, for one: pause rather than spin, and keep serving the others.
      spdlog::warn("HTTP accept failed: {}", ec.message());
      asio::steady_timer pause(executor_, accept_retry_pause);
      co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    const auto peer = socket.remote_endpoint(ec);
    if (ec || !options_.allow.allows(canonical_address(peer.address()))) {
      ++stats_.denied;
      spdlog::debug("HTTP client {} refused: not in [http] allow",
                    ec ? std::string("(unknown peer)") : peer.address().to_string());
      socket.close(ec);
      continue;
    }
    if (connections_.size() >= std::size_t(options_.max_clients)) {
      ++stats_.refused;
      socket.close(ec);
      continue;
    }
    ++stats_.accepted;
    auto connection = std::make_shared<Connection>(std::move(socket));
    connections_.insert(connection);
    asio::co_spawn(executor_, serve(connection), asio::detached);
  }
}

asio::awaitable<void> HttpServer::serve(std::shared_ptr<Connection> connection) {
  beast::flat_buffer buffer;
  for (;;) {
    http::request_parser<http::string_body> parser;
    parser.header_limit(std::uint32_t(options_.max_request_bytes));
    parser.body_limit(options_.max_request_bytes);
    // The whole request must be in within the time-out: a client trickling bytes is dropped.
    connection->stream.expires_after(options_.request_timeout);
    boost::system::error_code ec;
    co_await http::async_read(connection->stream, buffer, parser,
                              asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      // The client closed between requests: the normal end of a connection.
      if (ec != http::error::end_of_stream) ++stats_.dropped;
      if (ec == http::error::header_limit || ec == http::error::body_limit) {
        http::response<http::string_body> too_large{http::status::payload_too_large, 11};
        too_large.set(http::field::content_type, "text/plain; charset=utf-8");
        too_large.body() = "request too large\n";
        too_large.keep_alive(false);
        too_large.prepare_payload();
        co_await http::async_write(connection->stream, too_large,
                                   asio::redirect_error(asio::use_awaitable, ec));
      }
      break;
    }
    ++stats_.requests;
    const auto& request = parser.get();
    const HttpReply reply = route_http(std::string_view(request.method_string().data(),
                                                        request.method_string().size()),
                                       std::string_view(request.target().data(),
                                                        request.target().size()),
                                       status_, history_);
    http::response<http::string_body> response{http::status(reply.status), request.version()};
    response.set(http::field::server, "tiltgate");
    response.set(http::field::content_type, reply.content_type);
    response.set(http::field::cache_control, "no-store");
    if (reply.allow_get) response.set(http::field::allow, "GET, HEAD");
    if (!reply.content_disposition.empty())
      response.set(http::field::content_disposition, reply.content_disposition);
    response.keep_alive(request.keep_alive());
    response.body() = reply.body;
    response.prepare_payload();
    if (request.method() == http::verb::head) response.body().clear();
    co_await http::async_write(connection->stream, response,
                               asio::redirect_error(asio::use_awaitable, ec));
    if (ec || !response.keep_alive()) break;
  }
  connection->close();
  connections_.erase(connection);
}

}  // namespace tiltgate
