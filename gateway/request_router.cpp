#include "gateway/request_router.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "audit/audit_trail.h"
#include "gateway/alarm_acknowledgement.h"
#include "line_scheduling/bus_scheduler.h"
#include "gateway/pass_through_audit.h"
#include "gateway/router_reader.h"
#include "gateway/sensor_read.h"
#include "line_scheduling/sensor_write.h"
#include "gateway/unit_diagnostics.h"
#include "modbus_tcp/device_identification.h"
#include "modbus_tcp/diagnostics.h"
#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

namespace {

ModbusResponse failure(ModbusException code) {
  ModbusResponse response;
  response.exception = code;
  return response;
}

bool is_diagnostics(const ModbusRequest& request) {
  return request.function == modbus_function::diagnostics ||
         request.function == modbus_function::get_comm_event_counter;
}

// 08's reads and 11 from `counters` (gateway/unit_diagnostics.h); 08 0x0000 echoes the request.
void answer_diagnostics(const ModbusRequest& request, const SensorCounters& counters,
                        ModbusResponse& response) {
  if (request.function == modbus_function::get_comm_event_counter) {
    const CommEventCounter counter = comm_event_counter(counters);
    response.registers.assign({counter.status, counter.events});
  } else if (const auto count = diagnostic_count(counters, request.diagnostic)) {
    response.registers.assign({*count});
  } else if (request.diagnostic != diagnostic::return_query_data) {
    response.exception = ModbusException::illegal_function;
  }
}

// An aggregate unit's 08 and 11: its sensors' counts summed. Its counters are its sensors' to
// clear, each at its own unit: 0x000A is 01 here.
void answer_aggregate_diagnostics(const GatewayAggregate& aggregate, const ModbusRequest& request,
                                  ModbusResponse& response) {
  if (request.is_write) {
    response.exception = ModbusException::illegal_function;
    return;
  }
  SensorCounters total;
  for (const auto& member : aggregate.members)
    if (const auto snapshot = member->snapshot()) add_counts(total, snapshot->state.counters);
  answer_diagnostics(request, total, response);
}

}  // namespace

ModbusException exception_for(WriteErrorKind kind) {
  switch (kind) {
    case WriteErrorKind::not_supported: return ModbusException::illegal_address;
    case WriteErrorKind::bad_value:
    case WriteErrorKind::rejected: return ModbusException::illegal_value;
    case WriteErrorKind::refused: return ModbusException::device_failure;
    case WriteErrorKind::busy: return ModbusException::busy;
    case WriteErrorKind::no_response: return ModbusException::gateway_target_failed;
    case WriteErrorKind::device_exception: return ModbusException::device_failure;
  }
  return ModbusException::device_failure;
}

ModbusException exception_for(const WriteError& error) {
  if (error.kind == WriteErrorKind::device_exception && error.device_exception != 0)
    return ModbusException(error.device_exception);
  return exception_for(error.kind);
}

std::vector<DeviceObject> device_objects(const GatewaySensor& sensor, const SensorState& state) {
  // A model no family lists still answers, with what the driver calls it.
  const ProductIdentity product =
      sensor.model != nullptr ? sensor.model->identity
                              : ProductIdentity{"", sensor.driver->model(), sensor.driver->model()};
  return {
      {device_object::vendor_name, std::string(product.vendor)},
      {device_object::product_code, std::string(product.product_code)},
      {device_object::major_minor_revision, state.firmware},
      {device_object::product_name, std::string(product.product_name)},
      // The device's own model where its driver reads one (a device profile's [identity]).
      {device_object::model_name,
       state.model.empty() ? std::string(product.product_code) : state.model},
      {device_object::user_application_name, std::string("tiltgate ") + TILTGATE_VERSION},
      {device_object::serial_number, state.serial},
      {device_object::sensor_name, sensor.config.name},
      {device_object::bus_name, sensor.config.bus},
      {device_object::bus_address, std::to_string(state.bus_address)},
      {device_object::gateway_version, TILTGATE_VERSION},
  };
}

RequestRouter::RequestRouter(boost::asio::any_io_executor bus_executor, RouterOptions options)
    : bus_executor_(std::move(bus_executor)), routes_(std::make_shared<const Routes>(Routes{options})) {}

std::shared_ptr<const UnitRoutes> RequestRouter::routes() const {
  std::lock_guard lock(routes_mutex_);
  return routes_;
}

std::unique_ptr<ModbusReader> RequestRouter::reader() {
  return std::make_unique<RouterReader>(*this);
}

template <class Change>
void RequestRouter::edit(Change change) {
  if (draft_) {
    change(*draft_);
    return;
  }
  // A copy a few kB large per change: start-up only, never per request.
  auto edited = std::make_shared<Routes>(*routes());
  change(*edited);
  std::shared_ptr<const Routes> next = std::move(edited);
  std::lock_guard lock(routes_mutex_);
  routes_.swap(next);
  generation_.fetch_add(1, std::memory_order_release);
}

void RequestRouter::begin_update() {
  if (!draft_) draft_ = std::make_shared<Routes>(*routes());
}

void RequestRouter::commit_update() {
  if (!draft_) return;
  std::shared_ptr<const Routes> next = std::move(draft_);
  draft_.reset();
  std::lock_guard lock(routes_mutex_);
  routes_.swap(next);
  generation_.fetch_add(1, std::memory_order_release);
}

void RequestRouter::add(GatewaySensor& sensor) {
  // An empty owner: a pointer that keeps nothing alive.
  add(std::shared_ptr<GatewaySensor>(std::shared_ptr<GatewaySensor>(), &sensor));
}

void RequestRouter::add(std::shared_ptr<GatewaySensor> sensor) {
  edit([&](Routes& routes) { routes.units[sensor->config.unit_id] = std::move(sensor); });
}

void RequestRouter::add(std::shared_ptr<GatewayAggregate> aggregate) {
  edit([&](Routes& routes) { routes.aggregates[aggregate->config.unit_id] = std::move(aggregate); });
}

void RequestRouter::clear() {
  edit([](Routes& routes) {
    routes.units.fill(nullptr);
    routes.aggregates.fill(nullptr);
    routes.forwarded.fill(nullptr);
  });
}

void RequestRouter::set_options(RouterOptions options) {
  edit([&](Routes& routes) { routes.options = options; });
}

void RequestRouter::pass_through(std::uint8_t unit_id, std::shared_ptr<BusScheduler> bus) {
  edit([&](Routes& routes) { routes.forwarded[unit_id] = std::move(bus); });
}

bool answer_from_cache(const UnitRoutes& routes, const ModbusRequest& request,
                       const SensorSnapshot* snapshot, SteadyClock::time_point now,
                       ModbusResponse& response, CachedReadScratch& scratch) {
  response.exception.reset();
  response.registers.clear();
  response.bits.clear();
  response.device_objects.clear();
  const auto fail = [&](ModbusException code) {
    response.exception = code;
    return true;
  };
  const WordOrder order = routes.options.word_order;
  // An aggregate's reply is built in one call that does not suspend: one instant for all.
  if (const auto& aggregate = routes.aggregates[request.unit_id]) {
    if (is_diagnostics(request)) {
      answer_aggregate_diagnostics(*aggregate, request, response);
      return true;
    }
    read_aggregate_unit(*aggregate, request, order, now, response, scratch.aggregate);
    return true;
  }
  const GatewaySensor* sensor = routes.units[request.unit_id].get();
  if (sensor == nullptr) return fail(ModbusException::gateway_path_unavailable);
  if (request.is_write && request.function != modbus_function::encapsulated_interface) {
    // A gateway must not let anyone on the plant network re-address a sensor by default.
    if (!routes.options.writes) return fail(ModbusException::illegal_function);
    return false;
  }
  // Published when its bus takes it up: only a sensor routed but never polled has none.
  if (snapshot == nullptr) return fail(ModbusException::gateway_target_failed);
  if (request.function == modbus_function::encapsulated_interface) {
    // The encoder picks the objects the request asks for and pages them.
    response.device_objects = device_objects(*sensor, snapshot->state);
    return true;
  }
  if (is_diagnostics(request)) {
    answer_diagnostics(request, snapshot->state.counters, response);
    return true;
  }
  read_sensor(*sensor, *snapshot, request, order, now, response, scratch.image);
  return true;
}

boost::asio::awaitable<ModbusResponse> RequestRouter::handle(const ModbusRequest& request) {
  // One table for the whole request, whatever a reload routes meanwhile.
  const std::shared_ptr<const Routes> routes = this->routes();
  // Held until the request is done: a write waits for its bus, and a reload may drop the sensor
  // meanwhile; the write is still carried out and answered with its real outcome. A write
  // takes it along to the buses' thread, where it is then let go.
  std::shared_ptr<GatewaySensor> sensor = routes->units[request.unit_id];
  const std::shared_ptr<const SensorSnapshot> snapshot = sensor ? sensor->snapshot() : nullptr;
  ModbusResponse response;
  CachedReadScratch scratch;
  if (answer_from_cache(*routes, request, snapshot.get(), SteadyClock::now(), response, scratch))
    co_return response;
  if (stopping_) co_return failure(ModbusException::gateway_target_failed);
  co_return co_await boost::asio::co_spawn(
      bus_executor_, write(std::move(sensor), request, routes->options),
      boost::asio::use_awaitable);
}

// The router plans the registers into settings; the sensor's bus checks them, carries them
// out and answers (line_scheduling/sensor_write.h).
boost::asio::awaitable<ModbusResponse> RequestRouter::write(std::shared_ptr<GatewaySensor> sensor,
                                                            ModbusRequest request,
                                                            RouterOptions options) {
  if (request.function == modbus_function::diagnostics) co_return clear_counters(*sensor, request);
  if (request.table == ModbusTable::coil) co_return acknowledge_alarms(*sensor, request);
  if (request.table != ModbusTable::holding) {
    const auto table = table_of(request.table);
    co_return failure(sensor->map.has_table(table) ? ModbusException::illegal_address
                                                   : ModbusException::illegal_function);
  }
  auto plan = plan_register_write(sensor->map, options.word_order, request.address,
                                  request.registers);
  if (!plan) co_return failure(exception_for(plan.error()));
  // As for a read of a sensor never polled: no bus has taken it up.
  const std::shared_ptr<BusScheduler> bus = sensor->bus;
  if (bus == nullptr) co_return failure(ModbusException::gateway_target_failed);
  const auto deadline = SteadyClock::now() + options.write_timeout;
  // Named: see BusScheduler::write().
  SensorWrite write(std::move(sensor), std::move(*plan), std::move(request.origin));
  auto done = co_await bus->write(std::move(write), deadline);
  if (!done) co_return failure(exception_for(done.error()));
  co_return ModbusResponse{};
}

// 08 0x000A: the sensor's counters zeroed as the console's reset does (the one action,
// Gateway::reset_sensor_counters), and recorded in its bus's audit trail.
ModbusResponse RequestRouter::clear_counters(const GatewaySensor& sensor,
                                             const ModbusRequest& request) {
  AuditTrail* trail = sensor.bus ? sensor.bus->audit() : nullptr;
  const std::string name = sensor.config.bus + "/" + sensor.config.name;
  const auto record = [&](std::string result) {
    if (trail) trail->record({0, request.origin, name, "counters", "", "reset", std::move(result)});
  };
  // [audit] when_full = "refuse": no change the trail cannot keep on disk.
  if (trail && !trail->accepts_changes()) {
    std::string refused = "refused: ";
    refused += kAuditRefusesChanges;
    record(std::move(refused));
    return failure(ModbusException::device_failure);
  }
  if (!reset_counters_ || !reset_counters_(sensor.config.name)) {
    record("error: the sensor's counters are not this gateway's to reset");
    return failure(ModbusException::device_failure);
  }
  record("ok");
  return ModbusResponse{};
}

ModbusException exception_for(ForwardFailure failure) {
  switch (failure) {
    case ForwardFailure::busy: return ModbusException::busy;
    case ForwardFailure::expired:
    case ForwardFailure::no_response: return ModbusException::gateway_target_failed;
    case ForwardFailure::unframed: return ModbusException::device_failure;
    case ForwardFailure::standby: return ModbusException::gateway_path_unavailable;
  }
  return ModbusException::device_failure;
}

boost::asio::awaitable<ForwardedReply> RequestRouter::forward(std::uint8_t unit_id,
                                                              std::vector<std::uint8_t> pdu,
                                                              std::string client,
                                                              WriteOrigin origin) {
  const std::shared_ptr<const Routes> routes = this->routes();
  std::shared_ptr<BusScheduler> bus = routes->forwarded[unit_id];
  if (bus == nullptr) co_return Unexpected{ModbusException::gateway_path_unavailable};
  const bool may_change = !reads_only(pdu);
  // As for the cached sensors: nobody on the plant network changes a device by default.
  if (!routes->options.writes && may_change) {
    spdlog::debug("unit {}: function {:02X} not passed through: [server] writes is false",
                  unit_id, pdu.empty() ? 0 : pdu[0]);
    if (AuditTrail* trail = bus->audit())
      trail->record(pass_through_refusal(bus->name(), unit_id, pdu, "[server] writes is false",
                                         std::move(origin)));
    co_return Unexpected{ModbusException::illegal_function};
  }
  // [audit] when_full = "refuse": no change the trail cannot keep on disk.
  if (AuditTrail* trail = bus->audit(); may_change && trail && !trail->accepts_changes()) {
    trail->record(pass_through_refusal(bus->name(), unit_id, pdu, kAuditRefusesChanges,
                                       std::move(origin)));
    co_return Unexpected{ModbusException::device_failure};
  }
  if (stopping_) co_return Unexpected{ModbusException::gateway_target_failed};
  // The server's write_timeout bounds the wait for the bus, as it does for writes.
  const auto deadline = SteadyClock::now() + routes->options.write_timeout;
  // The bus serves its clients' requests in turn, each client known by its address.
  const std::uint64_t client_key = std::hash<std::string>{}(client);
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  std::optional<WriteOrigin> audit;
  if (may_change) audit = std::move(origin);
  std::optional<ForwardedReply> reply = co_await boost::asio::co_spawn(
      bus_executor_,
      forward_on_bus(std::move(bus), unit_id, std::move(pdu), deadline, client_key,
                     std::move(audit)),
      boost::asio::use_awaitable);
  co_return std::move(*reply);
}

// On the buses' executor: the scheduler is theirs. In an optional only because co_spawn wants
// a result it can default-construct.
boost::asio::awaitable<std::optional<ForwardedReply>> RequestRouter::forward_on_bus(
    std::shared_ptr<BusScheduler> bus, std::uint8_t unit_id, std::vector<std::uint8_t> pdu,
    SteadyClock::time_point deadline, std::uint64_t client, std::optional<WriteOrigin> audit) {
  // Kept for the record: the request is handed to the bus.
  std::vector<std::uint8_t> request = audit ? pdu : std::vector<std::uint8_t>{};
  auto reply = co_await bus->forward(unit_id, std::move(pdu), deadline, client);
  if (AuditTrail* trail = bus->audit(); audit && trail)
    trail->record(pass_through_record(bus->name(), unit_id, request, reply, std::move(*audit)));
  if (!reply) co_return ForwardedReply{Unexpected{exception_for(reply.error())}};
  co_return ForwardedReply{std::move(*reply)};
}

}  // namespace tiltgate
