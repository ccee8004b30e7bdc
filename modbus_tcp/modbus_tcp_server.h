// The Modbus TCP server: accepts clients, frames and checks their requests, asks the handler,
// and sends the replies. One coroutine per connection (epoll, so no FD_SETSIZE limit); a slow,
// silent or half-sent client only ever holds up itself. Accepting runs on the server's
// executor; each connection is served on one of the worker pool's threads, if there is one.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/common.h>
#include <chrono>
#include <cstdint>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <unordered_set>
#include <vector>

#include "config/address_allow_list.h"
#include "driver/expected.h"
#include "modbus_tcp/log_throttle.h"
#include "modbus_tcp/modbus_stream.h"
#include "modbus_tcp/modbus_request_counts.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

struct ModbusServerOptions {
  std::string listen = "0.0.0.0";  // an IP address literal (IPv4 or IPv6)
  std::uint16_t port = 502;        // 0 picks a free port (tests); see local_port()
  bool plain_tcp = true;           // false: TLS only
  // Modbus/TCP Security beside (or instead of) plain TCP, on `listen`:tls->port; TLS clients
  // share every limit, list and time-out below, and the handshake must end within
  // request_timeout.
  std::optional<ModbusTlsOptions> tls;
  // At max_clients a new client replaces the one idle longest, else it is accepted and closed
  // at once (modbus_tcp/connection_admission.h); an address holding max_clients_per_host replaces
  // its own connection idle longest, else it is closed.
  int max_clients = 32;
  int max_clients_per_host = 8;
  std::chrono::milliseconds idle_timeout{60000};    // no request for this long: closed
  std::chrono::milliseconds request_timeout{5000};  // a request (or its reply) stuck this long
                                                    // since its first byte: closed
  AddressAllowList allow;        // other clients are closed at accept
  AddressAllowList write_allow;  // other clients' writes (any function but a read) get 0x01
  LogThrottleOptions problem_log;  // clients closed for cause: a few lines per address, then counts
};

struct ModbusServerStats {
  std::uint64_t accepted = 0;          // connections served
  std::uint64_t refused = 0;           // connections closed at once: a limit reached, none idle
  std::uint64_t replaced = 0;          // idle connections closed to make room for a new one
  std::uint64_t denied = 0;            // connections closed at once: address not in allow
  std::uint64_t writes_denied = 0;     // writes answered 0x01: address not in write_allow
  std::uint64_t tls_refused = 0;       // TLS handshakes failed: no client certificate, one not
                                       // signed by the CA, or not TLS 1.2+
  std::uint64_t requests = 0;          // checked requests passed to the handler
  std::uint64_t forwarded = 0;         // requests for units passed through to a device
  std::uint64_t rejected = 0;          // malformed or unsupported: answered by the parser
  std::uint64_t framing_errors = 0;    // connections closed for a bad MBAP header
  std::uint64_t request_timeouts = 0;  // connections closed with a request or reply stuck
  std::uint64_t idle_timeouts = 0;     // connections closed for silence
};

class TcpWorkerPool;

// The listeners, admission, start(), stop() and apply() run on `executor`, which must be
// single-threaded (an io_context run by one thread). Connections are served on `workers`'
// threads (without workers: on `executor` too), so the handler must take requests from any
// of them at once; stats(), request_counts() and client_count() may be read from `executor`
// meanwhile. Call stop() and let the connections end (the event loop and the workers) before
// destroying the server.
class ModbusTcpServer {
 public:
  ModbusTcpServer(boost::asio::any_io_executor executor, ModbusRequestHandler& handler,
                  ModbusServerOptions options, TcpWorkerPool* workers = nullptr);
  ~ModbusTcpServer();
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  // Binds and listens, then accepts in the background. The error says what failed and where.
  Expected<Done, std::string> start();
  // The bound port (the ephemeral one when options.port is 0); 0 before start() or without
  // plain TCP.
  std::uint16_t local_port() const;
  // The same for Modbus/TCP Security; 0 without [server] tls.
  std::uint16_t tls_port() const;
  // Closes the acceptor and every connection; their coroutines end on the next loop turns.
  void stop();
  // New options for a running server (a reload), all of them at once; connected clients stay
  // connected and the next request, accept or deadline uses them. The listener is rebound only
  // when listen or port changed; when the new address cannot be bound, that is logged and the
  // server keeps listening where it did (options.listen and port stay the old ones).
  void apply(ModbusServerOptions options);

  // Open connections, not counting those closed and still winding down.
  std::size_t client_count() const;
  ModbusServerStats stats() const;
  // The options in force: apply() replaces them, connections read them request by request.
  std::shared_ptr<const ModbusServerOptions> options() const;
  const ModbusRequestCounts& request_counts() const { return request_counts_; }

 private:
  struct Connection;

  // Accepts until its acceptor closes; the plain one's loop also ends when a rebind starts a
  // newer loop (generation).
  boost::asio::awaitable<void> accept_clients(boost::asio::ip::tcp::acceptor& acceptor, bool tls,
                                              std::uint64_t generation);
  // apply(): moves the listener to `listen`:`port`; false (and logged) when it stays.
  bool rebind(const std::string& listen, std::uint16_t port);
  void admit(boost::asio::ip::tcp::socket socket, bool tls);
  void refuse(boost::asio::ip::tcp::socket socket, std::string_view limit);
  void replace(Connection& replaced, const std::string& by);
  boost::asio::awaitable<void> serve(std::shared_ptr<Connection> connection);
  boost::asio::awaitable<void> watch(std::shared_ptr<Connection> connection);
  boost::asio::awaitable<bool> answer(Connection& connection, std::span<const std::uint8_t> adu);
  boost::asio::awaitable<bool> send(Connection& connection, const std::vector<std::uint8_t>& reply);
  boost::asio::awaitable<ModbusResponse> ask_handler(const ModbusRequest& request);
  boost::asio::awaitable<std::vector<std::uint8_t>> forward(std::vector<std::uint8_t> adu);
  // The reply into `reply` (a connection's own buffer, reused request after request).
  void encode(const ModbusRequest& request, const ModbusResponse& response,
              std::vector<std::uint8_t>& reply);
  void expire(Connection& connection);
  void finish(const std::shared_ptr<Connection>& connection);
  // Logs why a client is closed, unless its address has had its share of lines lately.
  void log_closing(const Connection& connection, spdlog::level::level_enum level,
                   std::string_view why);
  void log_closing(const std::string& peer, const std::string& address,
                   spdlog::level::level_enum level, std::string_view why);
  // A refused request, throttled with the closes (it is the same client misbehaving).
  void log_problem(const std::string& peer, const std::string& address, std::string_view what);
  void log_suppressed(LogThrottle::Clock::time_point now);
  // One problem from `address`: true when it is to be logged in full (else it is counted).
  bool admit_problem(const std::string& address, LogThrottle::Clock::time_point now);
  boost::asio::awaitable<void> summarize_suppressed();

  // ModbusServerStats, counted from any thread.
  struct Counters {
    std::atomic<std::uint64_t> accepted{0}, refused{0}, replaced{0}, denied{0}, writes_denied{0},
        tls_refused{0}, requests{0}, forwarded{0}, rejected{0}, framing_errors{0},
        request_timeouts{0}, idle_timeouts{0};
  };
  // The options as `connection` last took them: a lock only after apply() changed them.
  const ModbusServerOptions& options_for(Connection& connection) const;
  // summarize_suppressed() is to wake before `due` (from any thread).
  void wake_summary_before(LogThrottle::Clock::time_point due);

  boost::asio::any_io_executor executor_;
  ModbusRequestHandler& handler_;
  TcpWorkerPool* workers_;  // none: connections on executor_
  mutable std::mutex options_mutex_;  // guards the pointer only
  std::shared_ptr<const ModbusServerOptions> options_;
  std::atomic<std::uint64_t> options_generation_{1};  // +1 by every apply()
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::ip::tcp::acceptor tls_acceptor_;
  std::unique_ptr<boost::asio::ssl::context> tls_context_;
  bool running_ = false;  // between start() and stop()
  mutable std::mutex connections_mutex_;
  std::unordered_set<std::shared_ptr<Connection>> connections_;
  Counters stats_;
  ModbusRequestCounts request_counts_;
  std::uint64_t accept_generation_ = 0;  // of the accept loop that may run
  bool refusing_ = false;  // warn once per burst of refused clients
  std::mutex problem_log_mutex_;
  LogThrottle problem_log_;
  boost::asio::steady_timer summary_timer_;  // wakes summarize_suppressed()
  std::atomic<LogThrottle::Clock::rep> summary_wake_{0};  // summary_timer_'s expiry
};

}  // namespace tiltgate
