// The Modbus TCP server: its listeners (plain and TLS) accept clients, admit, refuse or replace
// them, and it keeps the set of their connections (modbus_tcp_connection.h), which frame and
// check the requests, ask the handler and send the replies. Connections are served on the
// worker pool's event loops (epoll, so no FD_SETSIZE limit); a slow, silent or half-sent client
// only ever holds up itself. Accepting, and the handler's coroutines (writes, pass-through),
// run on the server's executor.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_set>

#include "driver/expected.h"
#include "doors/client_problem_log.h"
#include "modbus_tcp/modbus_request_counts.h"
#include "modbus_tcp/modbus_server_options.h"
#include "modbus_tcp/modbus_server_stats.h"
#include "modbus_tcp/modbus_tcp_connection.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

class TcpWorkerPool;

// The listeners, admission, start(), stop() and apply() run on `executor`, which must be
// single-threaded (an io_context run by one thread), and so do the handler's handle() and
// forward(). Connections are served on `workers`' threads (without workers: on one thread of
// the server's own), so the handler's reader() and passes_through() must take calls from any
// of them at once; stats(), request_counts() and client_count() may be read from `executor`
// meanwhile. Call stop() and let the connections end (the event loop and the workers) before
// destroying the server.
class ModbusTcpServer {
 public:
  // `workers`: the threads it serves its connections on (none: one of its own), whose request
  // rate (TcpWorkerPool::total_rate) every server on them shares; each server puts its
  // options' max_requests_per_s in force there.
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
  // Stopped, its accept loops and summary loop ended, and no connection left (a handler's
  // coroutine may hold one after it closed): it may be freed. On `executor`.
  bool finished() const;
  ModbusServerStats stats() const;
  // The options in force: apply() replaces them, connections read them request by request.
  std::shared_ptr<const ModbusServerOptions> options() const;
  const ModbusRequestCounts& request_counts() const { return request_counts_; }

 private:
  // Accepts until its acceptor closes; the plain one's loop also ends when a rebind starts a
  // newer loop (generation).
  boost::asio::awaitable<void> accept_clients(boost::asio::ip::tcp::acceptor& acceptor, bool tls,
                                              std::uint64_t generation);
  // apply(): moves the listener to `listen`:`port`; false (and logged) when it stays.
  bool rebind(const std::string& listen, std::uint16_t port);
  // Starts an accept loop on `acceptor`, counted in accept_loops_ until it ends.
  void spawn_accept(boost::asio::ip::tcp::acceptor& acceptor, bool tls);
  void admit(boost::asio::ip::tcp::socket socket, bool tls);
  void refuse(boost::asio::ip::tcp::socket socket, std::string_view limit);
  void replace(ModbusTcpConnection& replaced, const std::string& by);
  // A connection ended (on its own thread): it leaves the set.
  void forget(const std::shared_ptr<ModbusTcpConnection>& connection);

  boost::asio::any_io_executor executor_;
  std::unique_ptr<TcpWorkerPool> own_workers_;  // when none were given
  TcpWorkerPool* workers_;
  ModbusOptionsInForce options_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::ip::tcp::acceptor tls_acceptor_;
  std::unique_ptr<boost::asio::ssl::context> tls_context_;
  bool running_ = false;  // between start() and stop()
  mutable std::mutex connections_mutex_;
  std::unordered_set<std::shared_ptr<ModbusTcpConnection>> connections_;
  ModbusServerCounters stats_;
  ModbusRequestCounts request_counts_;
  std::uint64_t accept_generation_ = 0;  // of the accept loop that may run
  std::size_t accept_loops_ = 0;         // running
  bool refusing_ = false;  // warn once per burst of refused clients
  ClientProblemLog problem_log_;
  const ModbusConnectionContext connection_context_;  // what each connection sees of the server
};

}  // namespace tiltgate
