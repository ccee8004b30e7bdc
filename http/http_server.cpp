#include "modbus_tcp/tcp_listen.h"
#include "http/http_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <variant>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <vector>

#include "doors/connection_admission.h"
#include "modbus_tcp/tls_suites.h"
#include "http/host_check.h"
#include "http/http_request.h"
#include "http/http_response.h"

namespace tiltgate {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto accept_retry_pause = std::chrono::milliseconds(100);

std::string local_address_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint local = socket.local_endpoint(ec);
  return ec ? std::string() : local.address().to_string();
}

}  // namespace

struct HttpServer::Connection {
  using TlsStream = beast::ssl_stream<beast::tcp_stream>;
  Connection(tcp::socket socket, std::string address, bool from_troubled_address,
             asio::ssl::context* tls)
      : peer(peer_of(socket)),
        address(std::move(address)),
        local_address(local_address_of(socket)),
        from_troubled_address(from_troubled_address),
        waiting_since(Clock::now()),
        stream(make_stream(std::move(socket), tls)) {}
  static std::variant<beast::tcp_stream, TlsStream> make_stream(tcp::socket socket,
                                                               asio::ssl::context* tls) {
    if (tls == nullptr) return beast::tcp_stream(std::move(socket));
    return TlsStream(beast::tcp_stream(std::move(socket)), *tls);
  }
  beast::tcp_stream& lowest() {
    return std::visit([](auto& s) -> beast::tcp_stream& { return beast::get_lowest_layer(s); },
                      stream);
  }
  void close() {
    closed = true;
    boost::system::error_code ec;
    lowest().socket().shutdown(tcp::socket::shutdown_both, ec);
    lowest().socket().close(ec);
  }
  const std::string peer;     // "127.0.0.1:50312", for the log
  const std::string address;  // without the port: what max_clients_per_host counts
  const std::string local_address;  // the address it came in on: a Host that is always ours
  // Clients from its address were closed for cause lately (a flood reconnecting from many
  // addresses, say): while it waits, it gives way before the others.
  const bool from_troubled_address;
  // Waiting for a whole request since `waiting_since` (its accept, or its last response sent):
  // while it waits, a new client may close it to make room.
  bool waiting = true;
  Clock::time_point waiting_since;
  RateLimit own_rate;  // [http] max_client_requests_per_s
  bool served = false;  // it has answered a request: kept alive, it gives way first too
  bool signed_in = false;  // it has carried a request with a live console session
  bool closed = false;  // by stop() or to make room: its coroutine ends on a later loop turn
  std::variant<beast::tcp_stream, TlsStream> stream;
  beast::flat_buffer buffer;  // what was read of its requests and not yet parsed
};

struct HttpServer::Reading {
  explicit Reading(const HttpServerOptions& options) {
    parser.header_limit(std::uint32_t(options.max_request_bytes));
    parser.body_limit(options.max_body_bytes);
  }
  http::request_parser<http::string_body> parser;
  bool signed_in = true;  // no sessions ([http] users_file unset), or a live one
};

HttpServer::HttpServer(asio::any_io_executor executor, HttpHandler handler,
                       HttpServerOptions options)
    : executor_(executor),
      handler_(std::move(handler)),
      options_(std::move(options)),
      client_schedule_(RateSchedule::of(options_.max_client_requests_per_s)),
      total_rate_(options_.max_requests_per_s),
      anonymous_rate_(options_.signed_in ? options_.max_requests_per_s / 2.0 : 0),
      acceptor_(executor),
      problem_log_(executor, "HTTP", LogThrottleOptions{}) {}

HttpServer::~HttpServer() = default;

Expected<Done, std::string> HttpServer::start() {
  if (acceptor_.is_open()) return Unexpected{std::string("HTTP server already started")};
  if (!options_.tls_cert_pem.empty()) {
    tls_ = std::make_unique<asio::ssl::context>(asio::ssl::context::tls_server);
    boost::system::error_code ec;
    if (!offer_only_aead_suites(tls_->native_handle())) ec = asio::error::no_protocol_option;
    if (!ec) tls_->use_certificate_chain(asio::buffer(options_.tls_cert_pem), ec);
    if (!ec) tls_->use_private_key(asio::buffer(options_.tls_key_pem), asio::ssl::context::pem, ec);
    if (!ec && SSL_CTX_check_private_key(tls_->native_handle()) != 1)
      ec = asio::error::invalid_argument;
    if (ec) {
      tls_.reset();
      return Unexpected{fmt::format("[http] tls_cert_file / tls_key_file: {}",
                                    ec == asio::error::invalid_argument
                                        ? std::string("the key does not match the certificate")
                                        : ec.message())};
    }
  }
  if (auto listening = listen_on(acceptor_, options_.listen, options_.port, "HTTP"); !listening)
    return listening;
  spawn(accept_clients());
  problem_log_.start();
  return Done{};
}

std::uint16_t HttpServer::local_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

HttpServerStats HttpServer::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

void HttpServer::spawn(asio::awaitable<void> work) {
  ++coroutines_;
  asio::co_spawn(executor_, std::move(work), [this](std::exception_ptr) { --coroutines_; });
}

void HttpServer::stop() {
  boost::system::error_code ec;
  acceptor_.close(ec);
  problem_log_.stop();
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
    const std::string address = address_of(socket);
    if (!options_.allow.allows(address)) {
      count([](HttpServerStats& s) { ++s.denied; });
      spdlog::debug("HTTP client {} refused: not in [http] allow", address);
      socket.close(ec);
      continue;
    }
    if (!admit(socket, address)) {
      socket.close(ec);
      continue;
    }
    count([](HttpServerStats& s) { ++s.accepted; });
    auto connection = std::make_shared<Connection>(std::move(socket), address,
                                                   problem_log_.had_problems(address), tls_.get());
    connections_.insert(connection);
    spawn(serve(connection));
  }
}

bool HttpServer::admit(tcp::socket& socket, const std::string& address) {
  // Connections closed for an earlier client may still be winding down: they hold no place.
  std::vector<Connection*> live;
  std::vector<OpenConnection> open;
  std::size_t signed_in = 0;
  for (const auto& connection : connections_)
    signed_in += !connection->closed && connection->signed_in;
  // Logged-in users' connections keep their places up to half of them: anonymous newcomers make
  // room among each other (docs/web-console.md, "Logins and guessing").
  const bool keep_signed_in = signed_in <= std::size_t(options_.max_clients) / 2;
  for (const auto& connection : connections_) {
    if (connection->closed) continue;
    live.push_back(connection.get());
    const bool kept = keep_signed_in && connection->signed_in;
    // A new client's request may take a round trip to come; if the clients flooding the port
    // (from many addresses) went strictly by age, a burst of them could close it meanwhile.
    open.push_back({connection->address, connection->waiting && !kept, connection->waiting_since,
                    connection->served || connection->from_troubled_address});
  }
  const Admission admission = admit_connection(
      open, address,
      {std::size_t(options_.max_clients), std::size_t(options_.max_clients_per_host)});
  const std::string_view limit = admission.limit == AdmissionLimit::max_clients_per_host
                                     ? "max_clients_per_host"
                                     : "max_clients";
  if (!admission.admitted) {
    count([](HttpServerStats& s) { ++s.closed.refused; });
    problem_log_.log_closing(peer_of(socket), address, spdlog::level::warn,
                             fmt::format("{} reached and every connection busy answering", limit));
    return false;
  }
  if (admission.replaced) {
    Connection& replaced = *live[*admission.replaced];
    count([](HttpServerStats& s) { ++s.closed.replaced; });
    const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(
        Clock::now() - replaced.waiting_since);
    // A kept-alive connection left idle is no fault of its client: counted, not held against it.
    if (!replaced.served)
      problem_log_.log_closing(
          replaced.peer, replaced.address, spdlog::level::info,
          fmt::format("{} ms without a whole request, replaced by {} ({})", waited.count(),
                      peer_of(socket), limit));
    replaced.close();
  }
  return true;
}

void HttpServer::count_unserved(Connection& connection, boost::system::error_code ec,
                                bool got_some) {
  // Closed to make room or by stop(): counted there. Gone between requests: a normal end.
  if (connection.closed || ec == http::error::end_of_stream) return;
  if (ec == beast::error::timeout) {
    if (connection.served && !got_some) return;  // kept alive, then left idle: a normal end
    if (!got_some) {
      // Not a byte: a browser's preconnect (a socket opened in case a request follows), no
      // fault of anyone's. Neither counted nor held against its address.
      spdlog::debug("HTTP: {} closed: nothing sent within {} ms", connection.peer,
                    options_.request_timeout.count());
      return;
    }
    count([](HttpServerStats& s) { ++s.closed.timed_out; });
    problem_log_.log_closing(connection.peer, connection.address, spdlog::level::warn,
                             fmt::format("no whole request within {} ms",
                                         options_.request_timeout.count()));
  } else if (ec.category() == http::make_error_code(http::error::bad_target).category() &&
             ec != http::error::partial_message) {
    // Malformed or too large (a client that hung up mid-request is not counted).
    count([](HttpServerStats& s) { ++s.closed.bad_request; });
    problem_log_.log_closing(connection.peer, connection.address, spdlog::level::warn,
                             ec.message());
  }
}

Clock::time_point HttpServer::take_turn(Connection& connection, bool signed_in) {
  const Clock::time_point now = Clock::now();
  const Clock::time_point turn =
      signed_in ? next_turn(now, connection.own_rate, client_schedule_, total_rate_)
                : next_turn(now, connection.own_rate, client_schedule_, anonymous_rate_, total_rate_);
  if (turn <= now) return turn;
  count([&](HttpServerStats& s) {
    ++s.requests_delayed;
    s.delay_seconds += std::chrono::duration<double>(turn - now).count();
  });
  return turn;
}

asio::awaitable<void> HttpServer::serve(std::shared_ptr<Connection> connection) {
  if (auto* tls = std::get_if<Connection::TlsStream>(&connection->stream)) {
    // The handshake is part of the first request's time: a client that opens a connection
    // and says nothing is closed like one that sends half a request.
    connection->lowest().expires_after(options_.request_timeout);
    boost::system::error_code ec;
    co_await tls->async_handshake(asio::ssl::stream_base::server,
                                  asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      count_unserved(*connection, ec, false);
    } else {
      co_await serve_on(*connection, *tls);
    }
  } else {
    co_await serve_on(*connection, std::get<beast::tcp_stream>(connection->stream));
  }
  connection->close();
  connections_.erase(connection);
}

template <class Stream>
asio::awaitable<void> HttpServer::serve_on(Connection& connection, Stream& stream) {
  for (;;) {
    Reading reading(options_);
    if (const auto ec = co_await read_request(connection, stream, reading)) {
      co_await refuse_unread(connection, stream, ec, reading.parser.got_some());
      break;
    }
    if (connection.closed) break;  // made room for another after its request came in
    connection.waiting = false;
    connection.signed_in = connection.signed_in || (reading.signed_in && options_.signed_in);
    // Nothing more is read from it meanwhile.
    if (!co_await wait_turn(connection, reading.signed_in)) break;
    count([](HttpServerStats& s) { ++s.requests; });
    HttpRequest asked =
        http_request_of(reading.parser.get(), connection.address, tls_ != nullptr);
    // While the handler works (a console write waits for the sensor), the client's time-out
    // does not run: the reply's own time starts when it is ready.
    connection.lowest().expires_never();
    const HttpReply reply = co_await answer(connection, std::move(asked));
    if (connection.closed) break;
    if (!co_await send_reply(connection, stream, reading, reply)) break;
    connection.served = true;
    connection.waiting = true;
    connection.waiting_since = Clock::now();
  }
}

template <class Stream>
asio::awaitable<boost::system::error_code> HttpServer::read_request(Connection& connection,
                                                                    Stream& stream,
                                                                    Reading& reading) {
  // The whole request must be in within the time-out from the connection or the previous
  // response, however the bytes trickle in: a client sending a byte a second is dropped.
  connection.lowest().expires_after(options_.request_timeout);
  boost::system::error_code ec;
  co_await http::async_read_header(stream, connection.buffer, reading.parser,
                                   asio::redirect_error(asio::use_awaitable, ec));
  if (!ec && options_.signed_in) {
    reading.signed_in = options_.signed_in(header_of(reading.parser.get(), http::field::cookie));
    // No session: a few KiB, whatever the body says it holds (a login's is under 200 bytes).
    if (!reading.signed_in) ec = limit_body(reading.parser, options_.max_anonymous_body_bytes);
  }
  if (!ec && !reading.parser.is_done())
    co_await http::async_read(stream, connection.buffer, reading.parser,
                              asio::redirect_error(asio::use_awaitable, ec));
  co_return ec;
}

template <class Stream>
asio::awaitable<void> HttpServer::refuse_unread(Connection& connection, Stream& stream,
                                                boost::system::error_code ec, bool got_some) {
  count_unserved(connection, ec, got_some);
  if (ec != http::error::header_limit && ec != http::error::body_limit) co_return;
  http::response<http::string_body> too_large{http::status::payload_too_large, 11};
  too_large.set(http::field::content_type, "text/plain; charset=utf-8");
  too_large.body() = "request too large\n";
  too_large.keep_alive(false);
  too_large.prepare_payload();
  co_await http::async_write(stream, too_large, asio::redirect_error(asio::use_awaitable, ec));
}

asio::awaitable<bool> HttpServer::wait_turn(Connection& connection, bool signed_in) {
  const Clock::time_point turn = take_turn(connection, signed_in);
  if (turn <= Clock::now()) co_return true;
  asio::steady_timer wait(executor_, turn);
  boost::system::error_code ec;
  co_await wait.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  co_return !connection.closed;
}

asio::awaitable<HttpReply> HttpServer::answer(Connection& connection, HttpRequest asked) {
  // Checked before any route, for every request (DNS rebinding: http/host_check.h).
  const HostVerdict host = check_host(asked.host, options_.server_names, connection.local_address);
  if (host == HostVerdict::ours) co_return co_await handler_(std::move(asked));
  // Throttled per address; the Host shown escaped.
  problem_log_.log_problem(connection.peer, connection.address,
                           host == HostVerdict::missing
                               ? std::string("a request without a Host header: answered 400")
                               : fmt::format("Host \"{}\" is not among [http] server_names: "
                                             "answered 421",
                                             asked.host));
  co_return misdirected_reply(host, asked.host);
}

template <class Stream>
asio::awaitable<bool> HttpServer::send_reply(Connection& connection, Stream& stream,
                                             const Reading& reading, const HttpReply& reply) {
  const auto& request = reading.parser.get();
  http::response<http::string_body> response =
      http_response(reply, request.version(), tls_ != nullptr);
  response.keep_alive(request.keep_alive());
  response.prepare_payload();
  if (request.method() == http::verb::head) response.body().clear();
  connection.lowest().expires_after(options_.request_timeout);  // a client that takes nothing
  boost::system::error_code ec;
  co_await http::async_write(stream, response, asio::redirect_error(asio::use_awaitable, ec));
  co_return !ec && response.keep_alive();
}

}  // namespace tiltgate
