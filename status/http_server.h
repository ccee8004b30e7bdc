// The read-only HTTP server of the status API and metrics (docs/northbound.md, "HTTP status API and
// metrics"), HTTP/1.1 with Boost.Beast on the gateway's event loop. One coroutine per
// connection; each request is answered from a status copy taken at once, so it never waits
// for a bus. A client that does not send a whole request in time, sends too much, or comes
// when max_clients are connected is closed: it only ever holds up itself.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_set>

#include "config/address_allow_list.h"
#include "driver/expected.h"
#include "status/http_routes.h"

namespace tiltgate {

struct HttpServerOptions {
  std::string listen = "127.0.0.1";  // an IP address literal (IPv4 or IPv6)
  std::uint16_t port = 8080;         // 0 picks a free port (tests); see local_port()
  int max_clients = 16;              // the next client is accepted and closed at once
  // From the first byte (or the connection) to the end of a request's header; and the most
  // an idle kept-alive connection stays open.
  std::chrono::milliseconds request_timeout{5000};
  std::size_t max_request_bytes = 8192;  // header and body together; more: 400 and closed
  AddressAllowList allow;                // other clients are closed at accept
};

struct HttpServerStats {
  std::uint64_t accepted = 0;
  std::uint64_t refused = 0;    // max_clients reached
  std::uint64_t denied = 0;     // address not in allow
  std::uint64_t requests = 0;
  std::uint64_t dropped = 0;    // closed for a time-out or a malformed or oversized request
};

// Everything runs on `executor`, which must be single-threaded. Call stop() and let the event
// loop finish the connections before destroying the server.
class HttpServer {
 public:
  HttpServer(boost::asio::any_io_executor executor, StatusSource status, HttpServerOptions options,
             HistorySource history = {});
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  Expected<Done, std::string> start();
  std::uint16_t local_port() const;  // 0 before start()
  void stop();

  const HttpServerStats& stats() const { return stats_; }

 private:
  struct Connection;

  boost::asio::awaitable<void> accept_clients();
  boost::asio::awaitable<void> serve(std::shared_ptr<Connection> connection);

  boost::asio::any_io_executor executor_;
  StatusSource status_;
  HttpServerOptions options_;
  HistorySource history_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::unordered_set<std::shared_ptr<Connection>> connections_;
  HttpServerStats stats_;
};

}  // namespace tiltgate
