// The assembled product: buses, drivers, register maps and the Modbus TCP server, built from a
// validated Config. The buses and services run on one io_context (the caller's thread); the
// Modbus TCP connections on threads of their own ([server] threads).
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <optional>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "gateway/bus_scheduler.h"
#include "gateway/control_server.h"
#include "gateway/counter_rates.h"
#include "gateway/gateway_sensor.h"
#include "gateway/gateway_status.h"
#include "gateway/history_recorder.h"
#include "gateway/http_server.h"
#include "gateway/modbus_tcp_server.h"
#include "gateway/mqtt_feed.h"
#include "gateway/request_router.h"
#include "gateway/tcp_worker_pool.h"
#include "mapping/map_export.h"
#include "gateway/serial_options.h"
#include "serial/serial_line.h"

namespace tiltgate {

class Gateway {
 public:
  Gateway(boost::asio::io_context& io, const Config& config);
  ~Gateway();

  // Opens the buses (a missing tty is not fatal: it is retried with back-off) and binds the
  // Modbus server (fatal: the error says why). A control socket or an HTTP port that cannot
  // be had is only warned about: the PLC's service does not depend on them.
  Expected<Done, std::string> start();
  void stop();

  std::uint16_t port() const;
  // The ports of the buses' own listeners ([[bus]] tcp_port), in the order first used.
  std::vector<std::uint16_t> bus_ports() const;
  std::vector<UnitMap> unit_maps() const;
  // Every sensor's and bus's state now, for the HTTP status API and metrics.
  GatewayStatus status(SteadyClock::time_point now) const;
  // The HTTP port bound; 0 when [http] is off or its port could not be bound.
  std::uint16_t http_port() const;
  // The MQTT feed's counters; none when [mqtt] is off.
  std::optional<MqttStats> mqtt_stats() const;
  const std::vector<std::shared_ptr<GatewaySensor>>& sensors() const { return sensors_; }

  // Serves `loaded` (a valid configuration: SIGHUP re-read the file) from now on, keeping what
  // did not change (gateway/config_diff.h): the ttys of unchanged buses, the sensors (cache,
  // written registers, counters, history, queued writes) whose settings and bus did not
  // change, and the Modbus clients connected. Replaced and removed sensors' queued writes are
  // still carried out and answered; a removed or changed bus is closed once its queued writes
  // are done. [http], [mqtt] and the control socket restart only when their settings (or, for
  // the control socket, the buses) changed. Logs one summary line. In gateway_reload.cpp.
  void reload(const Config& loaded);
  // When the configuration served now was loaded (start-up or the last reload), local time.
  const std::string& loaded_at() const { return loaded_at_; }

 private:
  struct Bus {
    std::unique_ptr<SerialLine> line;
    std::unique_ptr<BusScheduler> scheduler;
  };
  // A [[bus]] tcp_port's listener: a router and a Modbus TCP server of its own, with
  // [server]'s limits, lists and time-outs (plain TCP only).
  struct BusListener {
    std::uint16_t port = 0;
    std::unique_ptr<RequestRouter> router;   // declared first: outlives the server
    std::unique_ptr<ModbusTcpServer> server;
  };

  // The router of a listener (config.h, listener_of): router_ for the main one; a bus
  // listener's is made (not started) when first asked for.
  RequestRouter& router_for(std::uint16_t listener);
  // The aggregates of config_, routed on their listeners; one that cannot be made is logged.
  void make_aggregates();
  // reload(): stops and retires the bus listeners whose port `loaded` no longer has.
  void retire_bus_listeners(const Config& loaded);
  // reload(): starts the bus listeners made since, applies [server] to the others.
  void start_or_apply_bus_listeners();
  // Every Modbus TCP server: the main one, then the bus listeners'.
  std::vector<const ModbusTcpServer*> servers() const;

  // A bus's line and scheduler, made (not started) and its pass-through unit ids routed.
  Bus make_bus(const BusConfig& config);
  // Starts the bus's line and its scheduler's loop; when a reload retires the scheduler, the
  // loop ends after its queued writes and the line is closed.
  void start_bus(Bus& bus);
  static boost::asio::awaitable<void> run_bus(BusScheduler& scheduler, SerialLine& line);
  // A sensor as the core serves it, polled by `bus` and answered by the router; none when its
  // model has no driver (the loader rejects those).
  std::shared_ptr<GatewaySensor> make_sensor(const SensorConfig& config, const BusConfig& bus_config,
                                             BusScheduler& bus);
  // The optional services, made from config_ (not started).
  void make_control();
  void make_http(const HistoryRecorder* previous);
  void make_mqtt();
  void start_control();
  void start_http();
  void start_mqtt();
  // The status page's history rings for the sensors now; the rings of sensors `previous` had
  // (by name) carry over when they hold as many samples.
  void make_history(const HistoryRecorder* previous);
  // For loaded_at(): the wall clock now, "2026-12-02 05:10:22".
  static std::string local_time_now();
  // Routes the bus's pass_through unit ids to its scheduler.
  void pass_through(const BusConfig& bus, BusScheduler& scheduler, bool announce);
  // Samples the poll and busy counters once a second, for the rates status() shows.
  boost::asio::awaitable<void> sample_counters();
  void record_counters(SteadyClock::time_point now);
  // Every [http] history_interval_ms: each sensor's angles into its history ring.
  boost::asio::awaitable<void> record_history();

  boost::asio::io_context& io_;
  Config config_;
  std::vector<Bus> buses_;  // buses_[i] serves config_.buses[i]
  // Buses a reload removed or changed, closed once their queued writes were done; and the
  // services a reload restarted, stopped. Kept until the gateway goes: a request coroutine
  // may still hold a pointer into them (RequestRouter::forward holds its bus; a stopped
  // server's connection coroutines end on later loop turns).
  std::vector<Bus> retired_buses_;
  std::vector<std::shared_ptr<void>> retired_services_;
  std::vector<std::shared_ptr<GatewaySensor>> sensors_;  // in config_.sensors' order
  std::string loaded_at_;
  // The Modbus TCP connections' threads ([server] threads). Everything else of the gateway (the
  // buses first) runs on io_, which a TCP flood therefore cannot hold up.
  std::unique_ptr<TcpWorkerPool> tcp_workers_;
  RequestRouter router_;  // the main listener's: units of buses without tcp_port
  std::unique_ptr<ModbusTcpServer> server_;
  std::vector<BusListener> bus_listeners_;
  std::unique_ptr<ControlServer> control_;  // none without [server] control_socket
  std::unique_ptr<HttpServer> http_;        // none with [http] enabled = false
  std::unique_ptr<HistoryRecorder> history_;  // the status page's graphs; none without http_
  boost::asio::steady_timer history_timer_;
  std::unique_ptr<MqttFeed> mqtt_;          // none without [mqtt]
  double start_seconds_ = 0;                // Unix time of construction
  boost::asio::steady_timer sample_timer_;
  bool stopping_ = false;
  CounterRates sensor_poll_rates_;  // each sensor's polls, ok and failed
  CounterRates bus_rates_;          // each bus's polls then its busy seconds
};

// After Gateway::stop() and io.stop(): runs the completions stop() queued (cancelled waits and
// reads), so every coroutine of the gateway ends on its own before the Gateway is destroyed.
// Otherwise ~io_context destroys them suspended, after the Gateway, and their locals'
// destructors touch freed objects. Gives up after 2 s.
void finish_stopped(boost::asio::io_context& io);

// The Modbus TCP server's options from [server]: the one place they are made, at start-up and
// at every reload.
ModbusServerOptions modbus_server_options(const ServerConfig& server);
// A bus listener's ([[bus]] tcp_port): the same, on `port`, plain TCP only.
ModbusServerOptions bus_listener_options(const ServerConfig& server, std::uint16_t port);

// Builds the register map a sensor serves: its model's built-in map, or the map its
// configuration describes (a map file or an inline map, checked when the config was loaded).
RegisterMap map_for(const SensorConfig& sensor);

}  // namespace tiltgate
