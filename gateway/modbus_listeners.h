// The gateway's Modbus TCP listeners: the main one on [server] port, answering every unit of the
// buses without a port of their own, and one per [[bus]] tcp_port, answering only that bus's
// sensors, aggregates and pass-through unit ids (config.h, listener_of). Each listener is a
// router (the unit-id table) and a Modbus TCP server of its own, with [server]'s limits, lists
// and time-outs (a bus listener: plain TCP only).
//
// A reload routes every unit anew between begin_reload() and commit_reload(): requests see
// the new tables only once all are made, listeners whose port is gone close, and new ones
// open.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "modbus_tcp/modbus_tcp_server.h"
#include "gateway/request_router.h"
#include "gateway/retired.h"
#include "modbus_tcp/tcp_worker_pool.h"

namespace tiltgate {

// The Modbus TCP server's options from [server]: the one place they are made, at start-up and
// at every reload.
ModbusServerOptions modbus_server_options(const ServerConfig& server);
// A bus listener's ([[bus]] tcp_port): the same, on `port`, plain TCP only.
ModbusServerOptions bus_listener_options(const ServerConfig& server, std::uint16_t port);

class ModbusListeners {
 public:
  // `bus_executor`: where the buses run (the routers hand writes there) and where the servers
  // accept; connections are served on `workers`' threads. `counter_reset`: what every
  // router does for 08 0x000A (RequestRouter::set_counter_reset).
  ModbusListeners(boost::asio::any_io_executor bus_executor, const ServerConfig& server,
                  TcpWorkerPool& workers,
                  std::function<bool(std::string_view)> counter_reset = nullptr);
  ~ModbusListeners();
  ModbusListeners(const ModbusListeners&) = delete;
  ModbusListeners& operator=(const ModbusListeners&) = delete;

  // The router of `listener` (kMainListener or a tcp_port); a bus listener is made, not
  // started, when first asked for.
  RequestRouter& router_for(std::uint16_t listener);
  // Binds every listener; the error says which could not be bound and why.
  Expected<Done, std::string> start();
  // Writes and forwarded requests still arriving are answered at once; every client closes.
  void stop();

  // A reload: the routers collect their new tables in drafts, emptied here; the listeners
  // whose port `loaded` no longer has close; listeners made from now on take `loaded`'s
  // [server].
  void begin_reload(const Config& loaded);
  // Hands the drafts over, applies the new [server] to every listener and opens the new ones.
  void commit_reload();

  // The main listener's port (the ephemeral one when [server] port is 0).
  std::uint16_t port() const;
  // The bus listeners' ports, in the order first used.
  std::vector<std::uint16_t> bus_ports() const;
  // Every server: the main one, then the bus listeners'.
  std::vector<const ModbusTcpServer*> servers() const;

 private:
  struct Listener {
    std::uint16_t port = 0;
    std::unique_ptr<RequestRouter> router;  // declared first: outlives the server
    std::unique_ptr<ModbusTcpServer> server;
    // Stopped and no connection left to answer through its router (Retired).
    bool finished() const { return server->finished(); }
  };

  RouterOptions router_options() const;
  // Stops a listener and keeps it until its last connection has ended: a request being
  // answered still holds its router.
  void retire(Listener listener);

  boost::asio::any_io_executor executor_;
  ServerConfig server_;
  TcpWorkerPool& workers_;
  std::function<bool(std::string_view)> counter_reset_;
  Listener main_;
  std::vector<Listener> bus_listeners_;
  Retired<Listener> retired_;
};

}  // namespace tiltgate
