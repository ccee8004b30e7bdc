// The accepting half of the Modbus TCP server: its listeners (plain and TLS), moving them on a
// reload, and which connections are admitted, replaced or refused.
#include "gateway/tcp_listen.h"
#include "gateway/modbus_tcp_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <algorithm>
#include <exception>
#include <spdlog/spdlog.h>
#include <tuple>
#include <variant>

#include "gateway/connection_admission.h"
#include "gateway/modbus_tcp_connection.h"

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto accept_retry_pause = std::chrono::milliseconds(100);

std::string peer_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  if (ec) return "(unknown peer)";
  const asio::ip::address address = canonical_ip(peer.address());
  if (address.is_v6()) return fmt::format("[{}]:{}", address.to_string(), peer.port());
  return fmt::format("{}:{}", address.to_string(), peer.port());
}

// The client's address without its port: what a flood of connections has in common, and what
// max_clients_per_host counts.
std::string address_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  return ec ? "(unknown peer)" : canonical_ip(peer.address()).to_string();
}

}  // namespace

Expected<Done, std::string> ModbusTcpServer::start() {
  if (running_) return Unexpected(std::string("Modbus server already started"));
  if (!options_.plain_tcp && !options_.tls)
    return Unexpected(std::string("neither plain TCP nor TLS: nothing to serve"));
  if (options_.max_clients < 1) return Unexpected(std::string("max_clients must be at least 1"));
  if (options_.max_clients_per_host < 1)
    return Unexpected(std::string("max_clients_per_host must be at least 1"));

  if (options_.tls) {
    auto context = make_tls_context(*options_.tls);
    if (!context) return Unexpected(context.error());
    tls_context_ = std::move(*context);
  }
  if (options_.plain_tcp) {
    if (auto listening = listen_on(acceptor_, options_.listen, options_.port, "Modbus TCP");
        !listening)
      return listening;
  }
  if (options_.tls) {
    if (auto listening =
            listen_on(tls_acceptor_, options_.listen, options_.tls->port, "Modbus/TCP Security");
        !listening) {
      boost::system::error_code ec;
      acceptor_.close(ec);
      return listening;
    }
    spdlog::info("Modbus/TCP Security (TLS, client certificates signed by {}) on {}:{}",
                 options_.tls->ca_file, options_.listen, tls_port());
  }

  running_ = true;
  if (options_.plain_tcp)
    asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_),
                   asio::detached);
  if (options_.tls)
    asio::co_spawn(executor_, accept_clients(tls_acceptor_, true, 0), asio::detached);
  asio::co_spawn(executor_, summarize_suppressed(), asio::detached);
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
  summary_timer_.cancel();
  // Each connection's coroutine removes it from the set when it sees the closed socket.
  for (const auto& connection : connections_) connection->close();
}

void ModbusTcpServer::apply(ModbusServerOptions options) {
  // The TLS listener and its context are made once, at start().
  const auto tls_key = [](const ModbusServerOptions& o) {
    return o.tls ? std::make_tuple(o.tls->cert_pem, o.tls->key_pem, o.tls->ca_pem, o.tls->port)
                 : std::make_tuple(std::string(), std::string(), std::string(), std::uint16_t(0));
  };
  if (tls_key(options) != tls_key(options_) || options.plain_tcp != options_.plain_tcp) {
    spdlog::warn("[server] tls and plain_tcp apply at the next start; the listeners stay as "
                 "they are");
    options.tls = options_.tls;
    options.plain_tcp = options_.plain_tcp;
  }
  if (acceptor_.is_open() && (options.listen != options_.listen || options.port != options_.port) &&
      !rebind(options.listen, options.port)) {
    options.listen = options_.listen;
    options.port = options_.port;
  }
  options_ = std::move(options);
}

bool ModbusTcpServer::rebind(const std::string& listen, std::uint16_t port) {
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
      if (auto back = listen_on(acceptor_, options_.listen, options_.port, "Modbus TCP"); !back)
        spdlog::critical("{}; {}: no Modbus TCP listener now", listening.error(), back.error());
      else
        spdlog::error("{}; still listening on {}:{}", listening.error(), options_.listen, old_port);
      asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_), asio::detached);
      return false;
    }
  }
  if (!listening) {
    spdlog::error("{}; still listening on {}:{}", listening.error(), options_.listen, old_port);
    return false;
  }
  // The old accept loop sees its acceptor closed (operation_aborted) and ends.
  acceptor_.close(ec);
  acceptor_ = std::move(fresh);
  asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_), asio::detached);
  spdlog::info("Modbus TCP now listening on {}:{}; connected clients stay", listen, local_port());
  return true;
}

std::size_t ModbusTcpServer::client_count() const {
  return std::size_t(std::count_if(connections_.begin(), connections_.end(),
                                   [](const auto& connection) { return !connection->closed; }));
}

ModbusServerStats ModbusTcpServer::stats() const {
  return stats_;
}

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
    // Connections closed for an earlier one may still be winding down: they hold no place.
    std::vector<Connection*> live;
    std::vector<OpenConnection> open;
    for (const auto& connection : connections_) {
      if (connection->closed) continue;
      live.push_back(connection.get());
      open.push_back({connection->address, connection->waiting_for == ModbusWait::idle,
                      connection->idle_since});
    }
    const std::string address = address_of(socket);
    if (!options_.allow.allows(address)) {
      ++stats_.denied;
      log_closing(peer_of(socket), address, spdlog::level::warn, "address not in [server] allow");
      boost::system::error_code ignored;
      socket.close(ignored);
      continue;
    }
    const Admission admission = admit_connection(
        open, address,
        {std::size_t(options_.max_clients), std::size_t(options_.max_clients_per_host)});
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
void ModbusTcpServer::replace(Connection& replaced, const std::string& by) {
  ++stats_.replaced;
  const auto idle_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - replaced.idle_since);
  log_closing(replaced, spdlog::level::info,
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
  ModbusStream stream = tls ? ModbusStream(std::move(socket), *tls_context_)
                            : ModbusStream(std::move(socket));
  auto connection =
      std::make_shared<Connection>(std::move(stream), std::move(peer), std::move(address));
  connections_.insert(connection);
  spdlog::debug("Modbus TCP client {} connected ({} connected)", connection->peer,
                connections_.size());
  asio::co_spawn(executor_, watch(connection), asio::detached);
  asio::co_spawn(executor_, serve(connection), asio::detached);
}

}  // namespace tiltgate
