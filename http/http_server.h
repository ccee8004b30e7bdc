// The HTTP server of the status API, the metrics and the web console (docs/northbound.md,
// docs/web-console.md): HTTP/1.1, or HTTPS with a certificate, with Boost.Beast on an event
// loop of its own (http/http_thread.h), never the buses'. One coroutine per connection; the
// handler decides each reply (http/http_routes.h, console/console_handler.h). A client that does not send a whole request in time, or sends too much, is closed:
// it only ever holds up itself. Places are shared as the Modbus TCP server shares them
// (doors/connection_admission.h): one address holds at most max_clients_per_host, and a
// full server makes room for a new client by closing the connection that has waited longest
// without a whole request (kept-alive ones between requests, and those from an address whose
// clients were closed for cause lately, first); one that is being answered is never closed for
// this. What is closed for cause is counted and logged, throttled per
// address (doors/client_problem_log.h).
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <functional>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "config/address_allow_list.h"
#include "driver/expected.h"
#include "gateway/gateway_status.h"
#include "doors/client_problem_log.h"
#include "doors/request_rate.h"
#include "http/http_routes.h"

namespace tiltgate {

struct HttpServerOptions {
  std::string listen = "127.0.0.1";  // an IP address literal (IPv4 or IPv6)
  std::uint16_t port = 8080;         // 0 picks a free port (tests); see local_port()
  int max_clients = 16;           // then a new client makes room, or is accepted and closed
  int max_clients_per_host = 8;   // from one address; its next replaces its own, or is closed
  // From the connection (or the end of the previous response) to the end of a whole request:
  // bytes trickling in do not extend it. Also the most a response may take to be sent.
  std::chrono::milliseconds request_timeout{5000};
  std::size_t max_request_bytes = 8192;  // the header; more: 413 and closed
  // The body: the read-only API takes none; the web console a configuration's text.
  std::size_t max_body_bytes = 8192;
  AddressAllowList allow;                // other clients are closed at accept
  // Requests a second answered from every client together and from each connection; a request
  // beyond them waits for its turn, its connection reading nothing meanwhile
  // (doors/request_rate.h). 0: no limit.
  int max_requests_per_s = 0;
  int max_client_requests_per_s = 0;
  std::string tls_cert_pem, tls_key_pem;  // both: HTTPS only
  // Whether a request's Cookie header names a live console session (docs/web-console.md,
  // "Logins and guessing"). With it, requests without one ("anonymous") get a body of at most
  // max_anonymous_body_bytes and half of max_requests_per_s, and connections that have carried
  // a signed-in request keep their places while they hold half of max_clients or fewer, so
  // a flood of anonymous clients leaves logged-in users at least half of the server. None:
  // every request is treated alike, as the read-only API always was.
  std::function<bool(std::string_view cookie_header)> signed_in;
  std::size_t max_anonymous_body_bytes = 4096;
  // The names a request's Host header may give (http/host_check.h); the address a request
  // came in on is always one. Any other: 421, and the request never reaches the handler.
  std::vector<std::string> server_names;
};

using HttpHandler = std::function<boost::asio::awaitable<HttpReply>(HttpRequest)>;

struct HttpServerStats {
  std::uint64_t accepted = 0;
  std::uint64_t denied = 0;     // address not in allow
  std::uint64_t requests = 0;
  HttpClientsClosed closed;     // for cause: refused, replaced, timed out, bad request
  std::uint64_t requests_delayed = 0;  // waited for their turn under the request rates
  double delay_seconds = 0;            // how long they waited, together
};

// Everything runs on `executor`, which must be single-threaded. Call stop() and let the event
// loop finish the connections before destroying the server.
class HttpServer {
 public:
  HttpServer(boost::asio::any_io_executor executor, HttpHandler handler, HttpServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  Expected<Done, std::string> start();
  std::uint16_t local_port() const;  // 0 before start()
  void stop();
  // Stopped, and its accept loop, every connection and its summary loop have ended: nothing
  // refers to it any more, so a reload that replaced it may free it.
  bool finished() const {
    return !acceptor_.is_open() && coroutines_ == 0 && problem_log_.finished();
  }

  // Any thread: the gateway's status reads them while the server runs on its own.
  HttpServerStats stats() const;

 private:
  struct Connection;

  boost::asio::awaitable<void> accept_clients();
  // Admits the new client `socket` within the limits, making room if it must; false: refused.
  bool admit(boost::asio::ip::tcp::socket& socket, const std::string& address);
  boost::asio::awaitable<void> serve(std::shared_ptr<Connection> connection);
  template <class Stream>
  boost::asio::awaitable<void> serve_on(Connection& connection, Stream& stream);
  // serve_on()'s steps, one request each.
  struct Reading;  // a request as it is read, and whether it carries a console session
  // Its header, its session, then its body, all within request_timeout.
  template <class Stream>
  boost::asio::awaitable<boost::system::error_code> read_request(Connection& connection,
                                                                 Stream& stream,
                                                                 Reading& reading);
  // A request not read whole: counted, logged, and answered 413 when it was too large.
  template <class Stream>
  boost::asio::awaitable<void> refuse_unread(Connection& connection, Stream& stream,
                                             boost::system::error_code ec, bool got_some);
  // Its turn under the request rates; false: the connection was closed meanwhile.
  boost::asio::awaitable<bool> wait_turn(Connection& connection, bool signed_in);
  // The handler's reply, or 400 / 421 for a Host that does not name the gateway.
  boost::asio::awaitable<HttpReply> answer(Connection& connection, HttpRequest asked);
  // Sends `reply`; false: the connection ends (failed, or not kept alive).
  template <class Stream>
  boost::asio::awaitable<bool> send_reply(Connection& connection, Stream& stream,
                                          const Reading& reading, const HttpReply& reply);
  // Runs `work` on the executor, counted in coroutines_ until it ends.
  void spawn(boost::asio::awaitable<void> work);
  // A connection that ended without a whole request: counted and logged, unless it was closed
  // for another reason already or was a kept-alive one simply left idle.
  void count_unserved(Connection& connection, boost::system::error_code ec, bool got_some);
  // When the request that just came in on `connection` may be answered (now, or later); an
  // anonymous one takes its turn within the anonymous share first.
  std::chrono::steady_clock::time_point take_turn(Connection& connection, bool signed_in);

  boost::asio::any_io_executor executor_;
  HttpHandler handler_;
  HttpServerOptions options_;
  RateSchedule client_schedule_;  // options_.max_client_requests_per_s
  SharedRateLimit total_rate_;    // options_.max_requests_per_s
  SharedRateLimit anonymous_rate_;  // half of it, for requests without a session
  std::unique_ptr<boost::asio::ssl::context> tls_;  // none: plain HTTP
  boost::asio::ip::tcp::acceptor acceptor_;
  std::unordered_set<std::shared_ptr<Connection>> connections_;
  template <class Change>
  void count(Change change) {
    std::lock_guard lock(stats_mutex_);
    change(stats_);
  }
  mutable std::mutex stats_mutex_;
  HttpServerStats stats_;
  ClientProblemLog problem_log_;
  std::size_t coroutines_ = 0;  // the accept loop and the connections being served
};

}  // namespace tiltgate
