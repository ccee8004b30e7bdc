// The gateway core, assembled from a validated Config: its buses (each a serial line and the
// scheduler that owns it), the sensors they poll, and the Modbus TCP listeners that answer for
// them. The buses run on one io_context (the caller's thread); the Modbus TCP connections on
// threads of their own ([server] threads). Services beside the core (HTTP, MQTT, the control
// socket) are attached by the composition root and run with it (gateway/gateway_service.h).
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <memory>
#include <vector>

#include "audit/audit_trail.h"
#include "config/config.h"
#include "driver/expected.h"
#include "capture/black_box.h"
#include "line_scheduling/bus_scheduler.h"
#include "gateway/counter_rates.h"
#include "gateway/recent_failures.h"
#include "line_scheduling/gateway_sensor.h"
#include "gateway/gateway_service.h"
#include "gateway/gateway_status.h"
#include "gateway/modbus_listeners.h"
#include "modbus_tcp/tcp_worker_pool.h"
#include "mapping/map_export.h"
#include "serial/serial_line.h"

namespace tiltgate {

class Gateway {
 public:
  // `families`: the sensor families `config` was loaded with (its protocols and models).
  Gateway(boost::asio::io_context& io, const Config& config, FamilyList families);
  ~Gateway();

  // Started, reloaded and stopped with the gateway from now on, after the core (stopped
  // before it). The service must outlive the gateway's event loop.
  void attach(GatewayService& service);

  // Who opens the buses' lines. By default each opens as its bus starts; a redundant pair's
  // controller (redundancy/redundancy_controller.h) takes them instead, and opens them only
  // while this gateway is the active one. Set before start().
  struct LineKeeper {
    std::function<void(const BusConfig&, SerialLine&, BusScheduler&)> start;  // a bus starts
    std::function<void(const BusScheduler&)> retire;  // a reload retired it
    std::function<void()> stop;                       // the gateway stops
  };
  void keep_lines_with(LineKeeper keeper) { line_keeper_ = std::move(keeper); }

  // Opens the buses (a missing tty is not fatal: it is retried with back-off) and binds the
  // Modbus listeners (fatal: the error says why), then starts the attached services.
  Expected<Done, std::string> start();
  // Once [server] user took effect (or at once without one): the services' start_as_user().
  void start_as_user();
  void stop();

  // Serves `loaded` (a valid configuration: SIGHUP re-read the file) from now on, keeping what
  // did not change (gateway/config_diff.h): the ttys of unchanged buses, the sensors (cache,
  // written registers, counters, queued writes) whose settings and bus did not change, and
  // the Modbus clients connected. Replaced and removed sensors' queued writes are still
  // carried out and answered; a removed or changed bus is closed once its queued writes are
  // done. Then every attached service reloads. Logs one summary line.
  void reload(const Config& loaded);

  // Where a sensor made from now on (a reload's) finds the baseline it starts with
  // (GatewaySensor::baseline): the monitoring's book of those set since the configuration
  // (monitoring/baseline_book.h). Unset: [[sensor]] baseline. On the gateway's executor.
  void baselines_from(std::function<Baseline(const SensorConfig&)> lookup) {
    baselines_ = std::move(lookup);
  }
  // Whether the system clock is synchronised (clock/clock_watch.h), for every bus's readings
  // (BusScheduler::set_clock_check()), those of now and those a reload makes. Before start().
  void check_clock_with(std::function<bool()> synchronised);

  // The audit trail the buses' writes and the services record into (audit/audit_trail.h): the
  // composition root's, given before start(); until then the gateway's own, in memory.
  void set_audit(AuditTrail& trail);
  AuditTrail& audit() const { return *audit_; }
  // The sensor families the configuration was loaded with.
  FamilyList families() const { return families_; }

  // The configuration served now, and when it was loaded (start-up or the last reload), local
  // time.
  const Config& config() const { return config_; }
  const std::string& loaded_at() const { return loaded_at_; }
  // How many configurations it has served: 1 from the start, one more at each reload applied
  // (a console apply's confirmation waits for the one after it, console/confirm_window.h).
  std::uint64_t loads() const { return loads_; }
  boost::asio::any_io_executor executor() const { return io_.get_executor(); }

  // The main Modbus listener's port, and the buses' own listeners' ([[bus]] tcp_port).
  std::uint16_t port() const { return listeners_.port(); }
  std::vector<std::uint16_t> bus_ports() const { return listeners_.bus_ports(); }
  std::vector<UnitMap> unit_maps() const;
  // Every sensor's and bus's state now, and the Modbus listeners' counters; the services add
  // their own (HTTP, MQTT).
  GatewayStatus status(SteadyClock::time_point now) const;
  const std::vector<std::shared_ptr<GatewaySensor>>& sensors() const { return sensors_; }
  // Sets the counters of the sensor, or of the bus and each of its sensors, back to zero, as
  // at a start: what /api/sensors, /api/buses, /metrics and the registers count (the bus's
  // line keeps its busy seconds, machine-held waits and overloaded attempts). False for a name
  // not served. On the gateway's executor.
  bool reset_sensor_counters(std::string_view sensor);
  bool reset_bus_counters(std::string_view bus);
  // Each bus's scheduler, in config().buses' order: what the control socket relays to.
  std::vector<std::shared_ptr<BusScheduler>> schedulers() const;
  // The black box of the bus of that name (capture/black_box.h), or null.
  std::shared_ptr<BlackBox> black_box(std::string_view bus) const;

 private:
  // A bus: its line and the scheduler that owns it (declared after it: goes first). Shared:
  // its sensors, the routes of its pass-through units and the control socket's sessions hold
  // its scheduler through scheduler_of(), which keeps the whole bus.
  struct Bus {
    // What its line carried lately; before the line, which records into it.
    std::shared_ptr<BlackBox> black_box;
    BusConfig config;
    std::unique_ptr<SerialLine> line;
    std::unique_ptr<BusScheduler> scheduler;
  };
  static std::shared_ptr<BusScheduler> scheduler_of(const std::shared_ptr<Bus>& bus) {
    return std::shared_ptr<BusScheduler>(bus, bus->scheduler.get());
  }

  // A bus's line and scheduler, made (not started) and its pass-through unit ids routed.
  std::shared_ptr<Bus> make_bus(const BusConfig& config);
  // Starts the bus's line and its scheduler's loop; when a reload retires the scheduler, the
  // loop ends after its queued writes and the line is closed.
  void start_bus(const std::shared_ptr<Bus>& bus);
  static boost::asio::awaitable<void> run_bus(std::shared_ptr<Bus> bus);
  // A sensor as the core serves it, polled by `bus` and answered by its listener's router;
  // none when its model has no driver (the loader rejects those).
  std::shared_ptr<GatewaySensor> make_sensor(const SensorConfig& config, const BusConfig& bus_config,
                                             const std::shared_ptr<Bus>& bus);
  // The aggregates of config_, routed on their listeners; one that cannot be made is logged.
  void make_aggregates();
  // Routes the bus's pass_through unit ids to its scheduler.
  void pass_through(const BusConfig& config, const std::shared_ptr<Bus>& bus, bool announce);
  // Frees the retired buses nothing holds any more but this gateway (once a second, and at
  // each reload): always on this thread, though the last other holder may have been a
  // Modbus TCP thread's request.
  void free_unused_buses();
  // reload(): the buses of `loaded`, keeping those `diff` keeps; the others retire. Returns the
  // indexes of the buses made anew, to be started once their sensors are added.
  std::vector<std::size_t> reload_buses(const Config& loaded, const ConfigDiff& diff);
  // reload(): the sensors of `loaded`, keeping those `diff` keeps.
  void reload_sensors(const Config& loaded, const ConfigDiff& diff);
  // The sensor's counters, line time and recent failures back to zero, its snapshot published;
  // the callers restart the rates once.
  void zero_counters(GatewaySensor& sensor);
  // Samples the poll and busy counters once a second, for the rates status() shows.
  boost::asio::awaitable<void> sample_counters();
  void record_counters(SteadyClock::time_point now);
  // For loaded_at(): the wall clock now, "2026-12-02 05:10:22".
  static std::string local_time_now();

  boost::asio::io_context& io_;
  FamilyList families_;
  Config config_;
  // Before the buses: their schedulers refer to the trail.
  AuditTrail own_audit_{""};
  AuditTrail* audit_ = &own_audit_;
  std::vector<std::shared_ptr<Bus>> buses_;  // buses_[i] serves config_.buses[i]
  // Buses a reload removed or changed, closed once their queued writes were done, until
  // nothing else holds them (free_unused_buses()).
  std::vector<std::shared_ptr<Bus>> retired_buses_;
  std::vector<std::shared_ptr<GatewaySensor>> sensors_;  // in config_.sensors' order
  std::string loaded_at_;
  std::uint64_t loads_ = 1;
  // The Modbus TCP connections' threads ([server] threads). Everything else of the gateway (the
  // buses first) runs on io_, which a TCP flood therefore cannot hold up.
  std::unique_ptr<TcpWorkerPool> tcp_workers_;
  ModbusListeners listeners_;
  std::vector<GatewayService*> services_;
  LineKeeper line_keeper_;
  std::function<Baseline(const SensorConfig&)> baselines_;  // baselines_from()
  std::function<bool()> clock_synchronised_;                 // check_clock_with()
  double start_seconds_ = 0;  // Unix time of construction
  boost::asio::steady_timer sample_timer_;
  bool stopping_ = false;
  CounterRates sensor_rates_;       // each sensor's polls (ok and failed), then its line seconds
  CounterRates bus_rates_;          // each bus's polls then its busy seconds
  RecentFailures recent_failures_;  // each sensor's over the last 10 minutes
};

// After Gateway::stop() and io.stop(): runs the completions stop() queued (cancelled waits and
// reads), so every coroutine of the gateway ends on its own before the Gateway is destroyed.
// Otherwise ~io_context destroys them suspended, after the Gateway, and their locals'
// destructors touch freed objects. Gives up after 2 s.
void finish_stopped(boost::asio::io_context& io);

// Builds the register map a sensor serves: its model's built-in map, or the map its
// configuration describes (a map file or an inline map, checked when the config was loaded).
RegisterMap map_for(FamilyList families, const SensorConfig& sensor);

}  // namespace tiltgate
