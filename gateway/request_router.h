// Answers checked Modbus requests: routes by unit id to a sensor, reads from its cache through
// its register map, plans register writes into the sensor's settings and hands each request to
// its bus as one write (line_scheduling/sensor_write.h), lists the sensor's identification objects for
// Read Device Identification (43 / 14), and forwards requests for unit ids a bus passes
// through.
//
// Threads: reader() and passes_through() may run on any Modbus TCP thread, many at once: each
// connection's reader answers reads there, from the sensors' snapshots. handle() and
// forward() take what needs a bus (writes, forwarded requests), which runs on the buses'
// executor while the request awaits it. The routing table is replaced whole
// (add(), clear(), set_options() on the buses' thread), so a request sees one table throughout.
#pragma once

#include <array>
#include <atomic>
#include <boost/asio/any_io_executor.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>

#include "config/config.h"
#include "gateway/gateway_aggregate.h"
#include "line_scheduling/gateway_sensor.h"
#include "mapping/register_image.h"
#include "gateway/unit_routes.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

enum class ForwardFailure;

class RequestRouter : public ModbusRequestHandler {
 public:
  // `bus_executor`: where the buses, their schedulers and the sensors' drivers run.
  RequestRouter(boost::asio::any_io_executor bus_executor, RouterOptions options);

  // Answers `sensor`'s unit id (which must be free). This overload does not own the sensor:
  // the caller keeps it alive.
  void add(GatewaySensor& sensor);
  // The same, and a request being answered keeps its sensor alive to the end, even when a
  // reload drops the sensor meanwhile.
  void add(std::shared_ptr<GatewaySensor> sensor);
  // Answers the aggregate's unit id (which must be free) from its sensors' caches.
  void add(std::shared_ptr<GatewayAggregate> aggregate);
  // Forgets every sensor, aggregate and pass-through unit id (a reload adds the new set at once).
  // Requests already being answered finish with the sensor or bus they started with.
  void clear();
  // Applies to the next request.
  void set_options(RouterOptions options);
  // Between these two (a reload), the changes above collect in a draft that requests do not
  // see; commit_update() hands them over at once, so no request finds a unit missing halfway.
  void begin_update();
  void commit_update();
  // What 08 0x000A (clear counters) does to a sensor, by name, on the buses' executor: the
  // gateway's reset of its counters (false: no such sensor).
  void set_counter_reset(std::function<bool(std::string_view)> reset) {
    reset_counters_ = std::move(reset);
  }
  // The gateway is stopping: writes and forwarded requests not yet handed to a bus are answered
  // 0x0B at once, so none waits for a bus that no longer runs.
  void stop() { stopping_ = true; }

  boost::asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) override;
  // A connection's cached reader of this router (gateway/router_reader.h).
  std::unique_ptr<ModbusReader> reader() override;

  // The table now, and how many tables came before it: a reader takes a new table only when
  // the generation moved (read it first: the table got is then at least that new).
  std::shared_ptr<const UnitRoutes> routes() const;
  std::uint64_t generation() const { return generation_.load(std::memory_order_acquire); }

  // Pass-through: requests for `unit_id` go to the device with that address on `bus`, under
  // the same write rule as the cached sensors. The unit id must be no sensor's.
  void pass_through(std::uint8_t unit_id, std::shared_ptr<BusScheduler> bus);
  // Asked of every request: a look under the lock, without taking a copy of the table.
  bool passes_through(std::uint8_t unit_id) const override {
    std::lock_guard lock(routes_mutex_);
    return routes_->forwarded[unit_id] != nullptr;
  }
  // A request that may change the device (every function but the reads) is recorded in the
  // bus's audit trail with its outcome, refused ones too (gateway/pass_through_audit.h).
  boost::asio::awaitable<ForwardedReply> forward(std::uint8_t unit_id,
                                                 std::vector<std::uint8_t> pdu,
                                                 std::string client, WriteOrigin origin) override;

 private:
  using Routes = UnitRoutes;

  // Replaces the table with a copy `change` has edited (the buses' thread only).
  template <class Change>
  void edit(Change change);

  // Runs on the buses' executor; the write holds the sensor to the end.
  boost::asio::awaitable<ModbusResponse> write(std::shared_ptr<GatewaySensor> sensor,
                                               ModbusRequest request, RouterOptions options);
  ModbusResponse clear_counters(const GatewaySensor& sensor, const ModbusRequest& request);
  boost::asio::awaitable<std::optional<ForwardedReply>> forward_on_bus(
      std::shared_ptr<BusScheduler> bus, std::uint8_t unit_id, std::vector<std::uint8_t> pdu,
      SteadyClock::time_point deadline, std::uint64_t client, std::optional<WriteOrigin> audit);

  boost::asio::any_io_executor bus_executor_;
  mutable std::mutex routes_mutex_;  // guards the pointer only
  std::shared_ptr<const Routes> routes_;
  std::atomic<std::uint64_t> generation_ = 0;  // tables swapped in so far
  std::shared_ptr<Routes> draft_;  // between begin_update() and commit_update()
  std::atomic<bool> stopping_ = false;
  std::function<bool(std::string_view)> reset_counters_;  // set before serving, then only read
};

ModbusException exception_for(ForwardFailure failure);

// What a caller of answer_from_cache() keeps from one request to the next, so that a read
// allocates nothing: an aggregate read's scratch, and the register image of the snapshot read
// (none: the read converts its points one by one).
struct CachedReadScratch {
  AggregateScratch aggregate;
  RegisterImage* image = nullptr;
};

// What `request` gets from `routes` without a bus at `now`, into `response` (its vectors keep
// their capacity): an aggregate's values; a sensor's values or identification from
// `snapshot`, its latest (null when it was never polled); or the exception for a unit not
// routed, a sensor never polled or a write [server] writes refuses. False for a write its bus
// carries out. RequestRouter::handle() and every connection's reader answer through this.
bool answer_from_cache(const UnitRoutes& routes, const ModbusRequest& request,
                       const SensorSnapshot* snapshot, SteadyClock::time_point now,
                       ModbusResponse& response, CachedReadScratch& scratch);

ModbusException exception_for(WriteErrorKind kind);
// The same, but a device's own Modbus exception is relayed with its code.
ModbusException exception_for(const WriteError& error);

// Every Read Device Identification object of a sensor (modbus_tcp/device_identification.h for
// the ids): vendor and product from its model, firmware and serial as the sensor reported
// them (empty until read), its name, bus and bus address, and the gateway's version; `state` is
// the sensor's (a snapshot's, off the buses' thread).
std::vector<DeviceObject> device_objects(const GatewaySensor& sensor, const SensorState& state);

}  // namespace tiltgate
