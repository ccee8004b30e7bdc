#include "gateway/modbus_listeners.h"

#include <algorithm>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace {

// Beyond write_timeout, what a request with the handler may take before the connection answers
// it 0x0B itself: the hops to the buses' thread and back.
constexpr std::chrono::seconds kHandlerMargin{5};

}  // namespace

ModbusServerOptions modbus_server_options(const ServerConfig& server) {
  ModbusServerOptions options;
  options.listen = server.listen;
  options.port = server.port;
  options.max_clients = server.max_clients;
  options.max_clients_per_host = server.max_clients_per_host;
  options.allow = server.allow;
  options.write_allow = server.write_allow;
  options.tls_roles = server.tls_roles;
  options.plain_tcp = server.plain_tcp;
  if (const auto& tls = server.tls)
    options.tls = ModbusTlsOptions{tls->cert_pem, tls->key_pem, tls->ca_pem,
                                   tls->cert_file, tls->key_file, tls->ca_file, tls->port};
  options.idle_timeout = server.idle_timeout;
  options.request_timeout = server.request_timeout;
  options.max_requests_per_s = server.max_requests_per_s;
  options.max_client_requests_per_s = server.max_client_requests_per_s;
  // The handler's own deadline is write_timeout; past it and a margin for the buses' thread,
  // something failed inside the gateway and the client gets its 0x0B.
  options.handler_timeout = server.write_timeout + kHandlerMargin;
  return options;
}

ModbusServerOptions bus_listener_options(const ServerConfig& server, std::uint16_t port) {
  ModbusServerOptions options = modbus_server_options(server);
  options.port = port;
  options.plain_tcp = true;
  options.tls.reset();
  return options;
}

ModbusListeners::ModbusListeners(boost::asio::any_io_executor bus_executor,
                                 const ServerConfig& server, TcpWorkerPool& workers,
                                 std::function<bool(std::string_view)> counter_reset)
    : executor_(std::move(bus_executor)), server_(server), workers_(workers),
      counter_reset_(std::move(counter_reset)), retired_(executor_) {
  main_.port = kMainListener;
  main_.router = std::make_unique<RequestRouter>(executor_, router_options());
  main_.router->set_counter_reset(counter_reset_);
  main_.server = std::make_unique<ModbusTcpServer>(
      executor_, *main_.router, modbus_server_options(server_), &workers_);
}

ModbusListeners::~ModbusListeners() = default;

RouterOptions ModbusListeners::router_options() const {
  return RouterOptions{server_.writes, server_.word_order, server_.write_timeout};
}

RequestRouter& ModbusListeners::router_for(std::uint16_t listener) {
  if (listener == kMainListener) return *main_.router;
  for (Listener& bus : bus_listeners_)
    if (bus.port == listener) return *bus.router;
  Listener made;
  made.port = listener;
  made.router = std::make_unique<RequestRouter>(executor_, router_options());
  made.router->set_counter_reset(counter_reset_);
  made.server = std::make_unique<ModbusTcpServer>(
      executor_, *made.router, bus_listener_options(server_, listener), &workers_);
  bus_listeners_.push_back(std::move(made));
  return *bus_listeners_.back().router;
}

Expected<Done, std::string> ModbusListeners::start() {
  if (auto listening = main_.server->start(); !listening) return listening;
  for (Listener& bus : bus_listeners_)
    if (auto listening = bus.server->start(); !listening) return listening;
  return Done{};
}

void ModbusListeners::stop() {
  // Writes and forwarded requests still arriving are answered at once, not queued for buses
  // that stop next.
  main_.router->stop();
  for (Listener& bus : bus_listeners_) bus.router->stop();
  main_.server->stop();
  for (Listener& bus : bus_listeners_) bus.server->stop();
}

void ModbusListeners::retire(Listener listener) {
  listener.server->stop();
  retired_.add(std::make_unique<Listener>(std::move(listener)));
}

void ModbusListeners::begin_reload(const Config& loaded) {
  // Listeners made from here on are made for the new [server].
  server_ = loaded.server;
  main_.router->begin_update();
  main_.router->clear();
  std::vector<Listener> kept;
  for (Listener& listener : bus_listeners_) {
    const bool used = std::any_of(loaded.buses.begin(), loaded.buses.end(), [&](const auto& bus) {
      return listener_of(bus) == listener.port;
    });
    if (!used) {
      // Its clients are closed; a request being answered still holds its router.
      spdlog::info("Modbus TCP port {} closed: no bus has it as tcp_port", listener.port);
      retire(std::move(listener));
      continue;
    }
    listener.router->begin_update();
    listener.router->clear();
    kept.push_back(std::move(listener));
  }
  bus_listeners_ = std::move(kept);
}

void ModbusListeners::commit_reload() {
  // Listeners made since begin_reload() have no draft: commit_update() leaves them as they are.
  main_.router->set_options(router_options());
  main_.router->commit_update();
  for (Listener& listener : bus_listeners_) {
    listener.router->set_options(router_options());
    listener.router->commit_update();
  }
  main_.server->apply(modbus_server_options(server_));
  std::vector<Listener> served;
  for (Listener& listener : bus_listeners_) {
    if (listener.server->local_port() != 0) {
      listener.server->apply(bus_listener_options(server_, listener.port));
      served.push_back(std::move(listener));
      continue;
    }
    if (auto started = listener.server->start(); !started) {
      spdlog::error("Modbus TCP port {} not served: {}", listener.port, started.error());
      retire(std::move(listener));
      continue;
    }
    spdlog::info("Modbus TCP port {} opened", listener.port);
    served.push_back(std::move(listener));
  }
  bus_listeners_ = std::move(served);
}

std::uint16_t ModbusListeners::port() const { return main_.server->local_port(); }

std::vector<std::uint16_t> ModbusListeners::bus_ports() const {
  std::vector<std::uint16_t> ports;
  for (const Listener& bus : bus_listeners_) ports.push_back(bus.server->local_port());
  return ports;
}

std::vector<const ModbusTcpServer*> ModbusListeners::servers() const {
  std::vector<const ModbusTcpServer*> all{main_.server.get()};
  for (const Listener& bus : bus_listeners_) all.push_back(bus.server.get());
  return all;
}

}  // namespace tiltgate
