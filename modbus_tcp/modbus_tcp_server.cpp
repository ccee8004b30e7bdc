#include "modbus_tcp/modbus_tcp_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <algorithm>
#include <spdlog/spdlog.h>
#include <tuple>
#include <vector>

#include "doors/connection_admission.h"
#include "modbus_tcp/tcp_listen.h"
#include "modbus_tcp/tcp_worker_pool.h"

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto accept_retry_pause = std::chrono::milliseconds(100);

}  // namespace

ModbusTcpServer::ModbusTcpServer(asio::any_io_executor executor, ModbusRequestHandler& handler,
                                 ModbusServerOptions options, TcpWorkerPool* workers)
    : executor_(executor),
      own_workers_(workers == nullptr ? std::make_unique<TcpWorkerPool>(1) : nullptr),
      workers_(workers != nullptr ? workers : own_workers_.get()),
      options_(std::move(options)),
      acceptor_(executor),
      tls_acceptor_(executor),
      problem_log_(executor, "Modbus TCP", options_.current()->problem_log),
      connection_context_{
          .handler = handler,
          .handler_executor = executor,
          .counters = stats_,
          .request_counts = request_counts_,
          .options = options_,
          .total_rate = workers_->total_rate(),
          .problem_log = problem_log_,
          .finished = [this](const std::shared_ptr<ModbusTcpConnection>& connection) {
            forget(connection);
          },
          .in_use = std::make_shared<int>(0),
      } {
  workers_->total_rate().set(options_.current()->max_requests_per_s);
}

ModbusTcpServer::~ModbusTcpServer() {
  // Its own thread ends first: the connections on it refer to the server.
  if (own_workers_) {
    if (running_) stop();
    own_workers_->stop();
  }
}

std::shared_ptr<const ModbusServerOptions> ModbusTcpServer::options() const {
  return options_.current();
}

Expected<Done, std::string> ModbusTcpServer::start() {
  if (running_) return Unexpected(std::string("Modbus server already started"));
  const auto current = options();
  if (!current->plain_tcp && !current->tls)
    return Unexpected(std::string("neither plain TCP nor TLS: nothing to serve"));
  if (current->max_clients < 1) return Unexpected(std::string("max_clients must be at least 1"));
  if (current->max_clients_per_host < 1)
    return Unexpected(std::string("max_clients_per_host must be at least 1"));

  if (current->tls) {
    auto context = make_tls_context(*current->tls);
    if (!context) return Unexpected(context.error());
    tls_context_ = std::move(*context);
  }
  if (current->plain_tcp) {
    if (auto listening = listen_on(acceptor_, current->listen, current->port, "Modbus TCP");
        !listening)
      return listening;
  }
  if (current->tls) {
    if (auto listening =
            listen_on(tls_acceptor_, current->listen, current->tls->port, "Modbus/TCP Security");
        !listening) {
      boost::system::error_code ec;
      acceptor_.close(ec);
      return listening;
    }
    spdlog::info("Modbus/TCP Security (TLS, client certificates signed by {}) on {}:{}",
                 current->tls->ca_file, current->listen, tls_port());
  }

  running_ = true;
  if (current->plain_tcp)
    spawn_accept(acceptor_, false);
  if (current->tls)
    spawn_accept(tls_acceptor_, true);
  problem_log_.start();
  return Done{};
}

std::uint16_t ModbusTcpServer::local_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

std::uint16_t ModbusTcpServer::tls_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = tls_acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

void ModbusTcpServer::stop() {
  running_ = false;
  boost::system::error_code ec;
  acceptor_.close(ec);
  tls_acceptor_.close(ec);
  problem_log_.stop();
  // Each connection's coroutine removes it from the set when it sees the closed socket.
  std::lock_guard lock(connections_mutex_);
  for (const auto& connection : connections_) connection->close();
}

void ModbusTcpServer::apply(ModbusServerOptions options) {
  const auto current = this->options();
  // The TLS listener and its context are made once, at start().
  const auto tls_key = [](const ModbusServerOptions& o) {
    return o.tls ? std::make_tuple(o.tls->cert_pem, o.tls->key_pem, o.tls->ca_pem, o.tls->port)
                 : std::make_tuple(std::string(), std::string(), std::string(), std::uint16_t(0));
  };
  if (tls_key(options) != tls_key(*current) || options.plain_tcp != current->plain_tcp) {
    spdlog::warn("[server] tls and plain_tcp apply at the next start; the listeners stay as "
                 "they are");
    options.tls = current->tls;
    options.plain_tcp = current->plain_tcp;
  }
  if (acceptor_.is_open() && (options.listen != current->listen || options.port != current->port) &&
      !rebind(options.listen, options.port)) {
    options.listen = current->listen;
    options.port = current->port;
  }
  workers_->total_rate().set(options.max_requests_per_s);
  options_.replace(std::move(options));
}

bool ModbusTcpServer::rebind(const std::string& listen, std::uint16_t port) {
  const auto current = options();
  const std::uint16_t old_port = local_port();
  tcp::acceptor fresh(executor_);
  auto listening = listen_on(fresh, listen, port, "Modbus TCP");
  boost::system::error_code ec;
  if (!listening && port == old_port) {
    // The same port on another address (0.0.0.0 to 127.0.0.1) collides with our own listener:
    // let it go first, and take it back if the new address cannot be had either.
    acceptor_.close(ec);
    listening = listen_on(fresh, listen, port, "Modbus TCP");
    if (!listening) {
      if (auto back = listen_on(acceptor_, current->listen, current->port, "Modbus TCP"); !back)
        spdlog::critical("{}; {}: no Modbus TCP listener now", listening.error(), back.error());
      else
        spdlog::error("{}; still listening on {}:{}", listening.error(), current->listen, old_port);
      spawn_accept(acceptor_, false);
      return false;
    }
  }
  if (!listening) {
    spdlog::error("{}; still listening on {}:{}", listening.error(), current->listen, old_port);
    return false;
  }
  // The old accept loop sees its acceptor closed (operation_aborted) and ends.
  acceptor_.close(ec);
  acceptor_ = std::move(fresh);
  spawn_accept(acceptor_, false);
  spdlog::info("Modbus TCP now listening on {}:{}; connected clients stay", listen, local_port());
  return true;
}

void ModbusTcpServer::spawn_accept(tcp::acceptor& acceptor, bool tls) {
  ++accept_loops_;
  asio::co_spawn(executor_, accept_clients(acceptor, tls, tls ? 0 : ++accept_generation_),
                 [this](std::exception_ptr) { --accept_loops_; });
}

bool ModbusTcpServer::finished() const {
  if (running_ || accept_loops_ > 0 || !problem_log_.finished()) return false;
  // Every connection has left the set (forget(), under the lock: what its thread did to the
  // server before is seen here), and none is left at all: only the server's own token.
  std::lock_guard lock(connections_mutex_);
  return connections_.empty() && connection_context_.in_use.use_count() == 1;
}

std::size_t ModbusTcpServer::client_count() const {
  std::lock_guard lock(connections_mutex_);
  return std::size_t(
      std::count_if(connections_.begin(), connections_.end(),
                    [](const auto& connection) { return !connection->is_closed(); }));
}

ModbusServerStats ModbusTcpServer::stats() const { return stats_.snapshot(); }

asio::awaitable<void> ModbusTcpServer::accept_clients(tcp::acceptor& acceptor, bool tls,
                                                      std::uint64_t generation) {
  // A rebind (apply()) moves a new plain acceptor into acceptor_ and starts a newer loop.
  while (acceptor.is_open() && (tls || generation == accept_generation_)) {
    boost::system::error_code ec;
    tcp::socket socket =
        co_await acceptor.async_accept(asio::redirect_error(asio::use_awaitable, ec));
    if (ec == asio::error::operation_aborted || !acceptor.is_open()) co_return;
    if (ec) {
      spdlog::warn("Modbus TCP accept failed: {}", ec.message());
      // Out of descriptors (EMFILE) fails again at once: pause instead of spinning.
      asio::steady_timer pause(executor_, accept_retry_pause);
      co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    const auto options = this->options();
    // Connections closed for an earlier one may still be winding down: they hold no place.
    std::vector<std::shared_ptr<ModbusTcpConnection>> live;
    std::vector<OpenConnection> open;
    {
      std::lock_guard lock(connections_mutex_);
      for (const auto& connection : connections_) {
        if (connection->is_closed()) continue;
        live.push_back(connection);
        open.push_back({connection->address(), connection->is_idle(), connection->idle_since()});
      }
    }
    const std::string address = address_of(socket);
    if (!options->allow.allows(address)) {
      ++stats_.denied;
      problem_log_.log_closing(peer_of(socket), address, spdlog::level::warn,
                               "address not in [server] allow");
      boost::system::error_code ignored;
      socket.close(ignored);
      continue;
    }
    const Admission admission = admit_connection(
        open, address,
        {std::size_t(options->max_clients), std::size_t(options->max_clients_per_host)});
    const std::string_view limit = admission.limit == AdmissionLimit::max_clients_per_host
                                       ? "max_clients_per_host"
                                       : "max_clients";
    if (!admission.admitted) {
      refuse(std::move(socket), limit);
      continue;
    }
    if (admission.replaced) replace(*live[*admission.replaced], peer_of(socket) + " (" +
                                                                  std::string(limit) + ")");
    admit(std::move(socket), tls);
  }
}

void ModbusTcpServer::refuse(tcp::socket socket, std::string_view limit) {
  ++stats_.refused;
  if (!refusing_) {
    spdlog::warn("Modbus TCP client {} refused: {} reached and no connection idle", peer_of(socket),
                 limit);
    refusing_ = true;
  }
  boost::system::error_code ec;
  socket.close(ec);
}

// An idle connection gives way to a new one: a PLC reconnecting after a cable pull, its old
// connection still half-open, or any client when idle ones fill the server.
void ModbusTcpServer::replace(ModbusTcpConnection& replaced, const std::string& by) {
  ++stats_.replaced;
  const auto idle_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
      Clock::now() - replaced.idle_since());
  problem_log_.log_closing(replaced.peer(), replaced.address(), spdlog::level::info,
                           fmt::format("idle for {} ms, replaced by {}", idle_ms.count(), by));
  replaced.close();
}

void ModbusTcpServer::admit(tcp::socket socket, bool tls) {
  refusing_ = false;
  ++stats_.accepted;
  boost::system::error_code ec;
  // Replies are small and the client waits for each one: do not hold them for Nagle.
  socket.set_option(tcp::no_delay(true), ec);
  std::string peer = peer_of(socket);
  std::string address = address_of(socket);
  // The socket leaves Asio here: its connection serves it on a worker's loop.
  const int fd = socket.release(ec);
  if (ec) {
    spdlog::warn("Modbus TCP client {} dropped: {}", peer, ec.message());
    return;
  }
  auto connection = std::make_shared<ModbusTcpConnection>(
      fd, tls ? tls_context_->native_handle() : nullptr, std::move(peer), std::move(address),
      connection_context_, workers_->next());
  std::size_t count = 0;
  {
    std::lock_guard lock(connections_mutex_);
    connections_.insert(connection);
    count = connections_.size();
  }
  spdlog::debug("Modbus TCP client {} connected ({} connected)", connection->peer(), count);
  connection->start();
}

void ModbusTcpServer::forget(const std::shared_ptr<ModbusTcpConnection>& connection) {
  std::size_t left = 0;
  {
    std::lock_guard lock(connections_mutex_);
    connections_.erase(connection);
    left = connections_.size();
  }
  spdlog::debug("Modbus TCP client {} disconnected ({} connected)", connection->peer(), left);
}

}  // namespace tiltgate
