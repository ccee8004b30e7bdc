#include "gateway/gateway.h"

#include "device_server/serial_line_maker.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <algorithm>
#include <ctime>
#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "driver/family.h"
#include "driver/visible_text.h"
#include "gateway/config_diff.h"
#include "gateway/line_hint.h"
#include "gateway/driver_registry.h"
#include "line_scheduling/line_budget.h"
#include "gateway/process_descriptors.h"
#include "gateway/serial_options.h"
#include "gateway/status_copy.h"
#include "mapping/map_definition.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::size_t tcp_threads(const ServerConfig& server) {
  return server.threads > 0 ? std::size_t(server.threads) : default_tcp_threads();
}

}  // namespace

void finish_stopped(boost::asio::io_context& io) {
  io.restart();
  io.run_for(std::chrono::seconds(2));
}

RegisterMap map_for(FamilyList families, const SensorConfig& sensor) {
  return build_map(families, sensor.map, sensor.model, sensor.family_options.device_values());
}

std::string Gateway::local_time_now() {
  return fmt::format("{:%Y-%m-%d %H:%M:%S}", fmt::localtime(std::time(nullptr)));
}

Gateway::Gateway(boost::asio::io_context& io, const Config& config, FamilyList families)
    : io_(io),
      families_(families),
      config_(config),
      tcp_workers_(std::make_unique<TcpWorkerPool>(tcp_threads(config.server))),
      listeners_(io.get_executor(), config.server, *tcp_workers_,
                 [this](std::string_view name) { return reset_sensor_counters(name); }),
      sample_timer_(io.get_executor()) {
  for (const BusConfig& bus : config_.buses) buses_.push_back(make_bus(bus));
  for (const SensorConfig& sc : config_.sensors) {
    std::size_t bus_index = 0;
    while (bus_index < config_.buses.size() && config_.buses[bus_index].name != sc.bus) ++bus_index;
    if (bus_index == config_.buses.size()) continue;  // the loader rejects this
    auto sensor = make_sensor(sc, config_.buses[bus_index], buses_[bus_index]);
    if (sensor) sensors_.push_back(std::move(sensor));
  }
  make_aggregates();
  start_seconds_ = std::chrono::duration<double>(
                       std::chrono::system_clock::now().time_since_epoch()).count();
  loaded_at_ = local_time_now();
}

Gateway::~Gateway() {
  // The connections' threads end first: their coroutines refer to the servers and routers.
  tcp_workers_->stop();
  // A bus and its sensors hold each other until it stops (BusScheduler::stop()).
  for (const auto& bus : buses_) bus->scheduler->stop();
}

void Gateway::attach(GatewayService& service) { services_.push_back(&service); }

void Gateway::check_clock_with(std::function<bool()> synchronised) {
  clock_synchronised_ = std::move(synchronised);
  for (const auto& bus : buses_) bus->scheduler->set_clock_check(clock_synchronised_);
}

void Gateway::set_audit(AuditTrail& trail) {
  audit_ = &trail;
  for (const auto& bus : buses_) bus->scheduler->set_audit(trail);
}

std::shared_ptr<Gateway::Bus> Gateway::make_bus(const BusConfig& config) {
  auto bus = std::make_shared<Bus>();
  SerialLineOptions options = serial_options_from(families_, config);
  options.exclusive = true;
  bus->black_box = std::make_shared<BlackBox>(config.black_box);
  bus->config = config;
  bus->line = make_serial_line(io_.get_executor(), options);
  bus->line->record_frames_to(bus->black_box.get());
  bus->scheduler = std::make_unique<BusScheduler>(io_.get_executor(), *bus->line, config.name);
  bus->scheduler->set_audit(*audit_);
  if (clock_synchronised_) bus->scheduler->set_clock_check(clock_synchronised_);
  pass_through(config, bus, true);
  return bus;
}

std::shared_ptr<GatewaySensor> Gateway::make_sensor(const SensorConfig& config,
                                                    const BusConfig& bus_config,
                                                    const std::shared_ptr<Bus>& bus) {
  auto sensor = std::make_shared<GatewaySensor>();
  sensor->config = config;
  sensor->model = find_model(families_, config.model).model;
  sensor->driver = make_driver(families_, config, bus_config);
  if (!sensor->driver) return nullptr;  // the loader rejects unknown models
  // Served as this sensor only while its serial answers (the commissioning commands, which
  // also make drivers, talk to whichever device is there).
  sensor->driver->expect_serial(config.serial);
  sensor->map = map_for(families_, config);
  sensor->written.assign(sensor->map.holding_end(), 0);
  sensor->stale_after = config.stale_after.value_or(default_stale_after(config.poll));
  sensor->baseline = baselines_ ? baselines_(config) : config.baseline.value_or(Baseline{});
  sensor->bus = scheduler_of(bus);
  bus->scheduler->add(sensor);
  listeners_.router_for(listener_of(bus_config)).add(sensor);
  return sensor;
}

void Gateway::make_aggregates() {
  for (const AggregateConfig& config : config_.aggregates) {
    auto aggregate = make_gateway_aggregate(config, sensors_);
    if (!aggregate) {
      spdlog::error("aggregate unit {} (line {}) not served: {}", config.unit_id, config.line,
                    aggregate.error());
      continue;
    }
    listeners_.router_for(listener_of(config_, config)).add(std::move(*aggregate));
  }
}

void Gateway::pass_through(const BusConfig& config, const std::shared_ptr<Bus>& bus,
                           bool announce) {
  if (config.pass_through.empty()) return;
  const ProtocolEntry protocol = find_protocol(families_, config.protocol);
  if (protocol.protocol == nullptr || protocol.protocol->forward == nullptr) return;  // refused
  bus->scheduler->enable_forwarding(protocol.protocol->forward);
  RequestRouter& router = listeners_.router_for(listener_of(config));
  for (std::uint8_t unit_id : config.pass_through) router.pass_through(unit_id, scheduler_of(bus));
  if (announce)
    spdlog::info("bus {}: unit id(s) {} passed through", config.name,
                 fmt::join(config.pass_through, ", "));
}

Expected<Done, std::string> Gateway::start() {
  if (auto listening = listeners_.start(); !listening) return listening;
  for (const auto& bus : buses_) start_bus(bus);
  boost::asio::co_spawn(io_, sample_counters(), boost::asio::detached);
  spdlog::info("serving {} sensor(s) on {} bus(es), Modbus TCP {}:{} ({} thread(s)){}",
               sensors_.size(), buses_.size(), config_.server.listen, listeners_.port(),
               tcp_workers_->size(), config_.server.writes ? ", writes enabled" : "");
  for (const BusConfig& bus : config_.buses)
    if (bus.tcp_port) spdlog::info("bus {}: its units on Modbus TCP port {}", bus.name, *bus.tcp_port);
  for (const std::string& warning : line_budget_warnings(config_, families_))
    spdlog::warn("{}", visible_text(warning));
  for (GatewayService* service : services_) service->start();
  return Done{};
}

void Gateway::start_as_user() {
  for (GatewayService* service : services_) service->start_as_user();
}

void Gateway::start_bus(const std::shared_ptr<Bus>& bus) {
  if (line_keeper_.start)
    line_keeper_.start(bus->config, *bus->line, *bus->scheduler);
  else
    bus->line->start();
  boost::asio::co_spawn(io_, run_bus(bus), boost::asio::detached);
}

// Holds the bus while its loop runs.
boost::asio::awaitable<void> Gateway::run_bus(std::shared_ptr<Bus> bus) {
  co_await bus->scheduler->run();
  // A bus a reload retired lets its tty go once its queued writes are done; at shutdown,
  // stop() closes every line itself.
  if (bus->scheduler->retiring()) bus->line->stop();
}

void Gateway::free_unused_buses() {
  std::erase_if(retired_buses_, [](const std::shared_ptr<Bus>& bus) { return bus.use_count() == 1; });
}

void Gateway::stop() {
  stopping_ = true;
  sample_timer_.cancel();
  listeners_.stop();
  for (GatewayService* service : services_) service->stop();
  if (line_keeper_.stop) line_keeper_.stop();
  for (const auto* buses : {&buses_, &retired_buses_})
    for (const auto& bus : *buses) {
      bus->scheduler->stop();
      bus->line->stop();
    }
}

void Gateway::reload(const Config& loaded) {
  const ConfigDiff diff = diff_configs(config_, loaded);
  if (loaded.server.threads != config_.server.threads)
    spdlog::warn("[server] threads applies at the next start; still {} thread(s)",
                 tcp_workers_->size());
  config_ = loaded;

  // Every listener's units are routed anew; requests see the new routes only once all are
  // made (commit_reload() below).
  listeners_.begin_reload(loaded);
  const std::vector<std::size_t> fresh_buses = reload_buses(loaded, diff);
  reload_sensors(loaded, diff);
  // Aggregates are rebuilt over the sensors served now (kept or new).
  make_aggregates();
  for (std::size_t index : fresh_buses) start_bus(buses_[index]);
  free_unused_buses();
  listeners_.commit_reload();

  if (!diff.buses_unchanged() || !diff.sensors_unchanged()) {
    // The rates are kept per position; positions moved.
    sensor_rates_ = CounterRates{};
    bus_rates_ = CounterRates{};
    std::vector<std::string> names;
    for (const SensorConfig& sensor : config_.sensors) names.push_back(sensor.name);
    recent_failures_.keep_only(names);
  }
  std::vector<std::string_view> restarted;
  for (GatewayService* service : services_)
    if (service->reload(config_, diff)) restarted.push_back(service->name());
  loaded_at_ = local_time_now();
  ++loads_;
  spdlog::info("configuration reloaded from {}: {}{}{}", visible_text(config_.path),
               summarize(diff),
               restarted.empty() ? "" : ". restarted: ", fmt::join(restarted, ", "));
  for (const std::string& warning : line_budget_warnings(config_, families_))
    spdlog::warn("{}", visible_text(warning));
}

std::vector<std::size_t> Gateway::reload_buses(const Config& loaded, const ConfigDiff& diff) {
  // In the new file's order: the unchanged ones as they are (tty open, scheduler and queued
  // writes untouched), the others made anew, started once their sensors are added.
  std::vector<std::shared_ptr<Bus>> old_buses = std::move(buses_);
  buses_.clear();
  std::vector<std::size_t> fresh;
  for (const BusConfig& config : loaded.buses) {
    auto old = std::find_if(old_buses.begin(), old_buses.end(), [&](const auto& bus) {
      return bus && bus->scheduler->name() == config.name;
    });
    if (listed(diff.buses_kept, config.name) && old != old_buses.end()) {
      pass_through(config, *old, false);
      buses_.push_back(std::move(*old));  // taken: *old is empty now
    } else {
      buses_.push_back(make_bus(config));
      fresh.push_back(buses_.size() - 1);
    }
  }
  // Removed and changed buses: no more polls; their queued writes finish, then the tty closes.
  for (auto& bus : old_buses) {
    if (!bus) continue;
    if (line_keeper_.retire) line_keeper_.retire(*bus->scheduler);
    bus->scheduler->retire();
    retired_buses_.push_back(std::move(bus));
  }
  return fresh;
}

void Gateway::reload_sensors(const Config& loaded, const ConfigDiff& diff) {
  // In the new file's order: unchanged ones keep their object (cache, written registers,
  // counters, queued writes); the others are made anew on their bus.
  std::vector<std::shared_ptr<GatewaySensor>> old_sensors = std::move(sensors_);
  sensors_.clear();
  for (const SensorConfig& config : loaded.sensors) {
    auto old = std::find_if(old_sensors.begin(), old_sensors.end(), [&](const auto& sensor) {
      return sensor && sensor->config.name == config.name;
    });
    if (listed(diff.sensors_kept, config.name) && old != old_sensors.end()) {
      // Where it is declared may have moved; nothing else differs (same_settings). Only that
      // field is written: the Modbus TCP threads read the rest meanwhile.
      (*old)->config.line = config.line;
      listeners_.router_for(listener_of(loaded, config)).add(*old);
      sensors_.push_back(std::move(*old));
      continue;
    }
    std::size_t bus = 0;
    while (bus < loaded.buses.size() && loaded.buses[bus].name != config.bus) ++bus;
    if (bus == loaded.buses.size()) continue;  // the loader rejects this
    if (auto sensor = make_sensor(config, loaded.buses[bus], buses_[bus]))
      sensors_.push_back(std::move(sensor));
  }
  // Removed and replaced sensors leave their bus's polls (a retired bus has none left). Their
  // queued writes still run: each request being answered holds its sensor.
  for (const auto& sensor : old_sensors)
    if (sensor && sensor->bus != nullptr) sensor->bus->remove(*sensor);
}

asio::awaitable<void> Gateway::sample_counters() {
  while (!stopping_) {
    record_counters(SteadyClock::now());
    free_unused_buses();
    sample_timer_.expires_after(std::chrono::seconds(1));
    boost::system::error_code ec;
    co_await sample_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

void Gateway::record_counters(SteadyClock::time_point now) {
  // Each sensor's polls then its line seconds.
  std::vector<double> sensors;
  for (const auto& sensor : sensors_) {
    const SensorCounters& counters = sensor->driver->state().counters;
    sensors.push_back(double(counters.polls_ok) + double(counters.polls_failed));
    sensors.push_back(std::chrono::duration<double>(sensor->line_time).count());
    recent_failures_.record(sensor->config.name, now, failure_counts(counters));
  }
  sensor_rates_.record(now, std::move(sensors));
  std::vector<double> buses;
  for (const auto& bus : buses_) {
    const BusSchedulerStats& stats = bus->scheduler->stats();
    buses.push_back(double(stats.polls));
    buses.push_back(std::chrono::duration<double>(stats.busy).count());
  }
  bus_rates_.record(now, std::move(buses));
}

GatewayStatus Gateway::status(SteadyClock::time_point now) const {
  GatewayStatus status;
  status.loaded_at = loaded_at_;
  status.audit = audit_->counts();
  status.audit_health = audit_->health();
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    status.sensors.push_back(sensor_status(*sensors_[i], now));
    status.sensors.back().recent_failures = recent_failures_.of(
        sensors_[i]->config.name, failure_counts(sensors_[i]->driver->state().counters));
    status.sensors.back().polls_per_s = rounded(sensor_rates_.rate(2 * i), 100);
    // As for a bus's utilisation, a turn across the sample instant counts wholly later.
    if (const auto share = rounded(sensor_rates_.rate(2 * i + 1), 1000))
      status.sensors.back().line_share = std::min(*share, 1.0);
  }
  for (std::size_t i = 0; i < buses_.size(); ++i) {
    status.buses.push_back(bus_status(config_.buses[i], buses_[i]->scheduler->stats(),
                                      buses_[i]->line->stats(), bus_rates_.rate(2 * i),
                                      bus_rates_.rate(2 * i + 1)));
    const BlackBox& box = *buses_[i]->black_box;
    status.buses.back().black_box_s = box.keep().count();
    status.buses.back().black_box_frames = box.frames_held();
    status.buses.back().black_box_bytes = box.bytes_held();
    status.buses.back().black_box_dropped = box.dropped();
    add_sensor_failures(status.buses.back(), status.sensors);
    status.buses.back().hint = line_hint(status.buses.back(), status.sensors);
  }
  // Totals over every listener: the main one and the buses' own ([[bus]] tcp_port).
  for (const ModbusTcpServer* listener : listeners_.servers()) add_listener_counts(status, *listener);
  status.modbus_max_requests_per_s = config_.server.max_requests_per_s;
  status.modbus_max_client_requests_per_s = config_.server.max_client_requests_per_s;
  status.process_start_seconds = start_seconds_;
  if (const auto descriptors = process_descriptors()) {
    status.process_open_fds = descriptors->open;
    status.process_max_fds = descriptors->max;
  }
  return status;
}

void Gateway::zero_counters(GatewaySensor& sensor) {
  sensor.driver->reset_counters();
  sensor.line_time = {};
  sensor.publish();  // the registers that serve the counters read zero at once
  recent_failures_.forget(sensor.config.name);
}

bool Gateway::reset_sensor_counters(std::string_view name) {
  for (const auto& sensor : sensors_)
    if (sensor->config.name == name) {
      zero_counters(*sensor);
      // The rates start over from the counters as they are now.
      sensor_rates_.clear();
      record_counters(SteadyClock::now());
      return true;
    }
  return false;
}

bool Gateway::reset_bus_counters(std::string_view name) {
  for (std::size_t i = 0; i < buses_.size(); ++i) {
    if (config_.buses[i].name != name) continue;
    for (const auto& sensor : sensors_)
      if (sensor->config.bus == name) zero_counters(*sensor);
    buses_[i]->scheduler->reset_counters();
    // Once for the bus and all its sensors, not once a sensor.
    sensor_rates_.clear();
    bus_rates_.clear();
    record_counters(SteadyClock::now());
    return true;
  }
  return false;
}

std::shared_ptr<BlackBox> Gateway::black_box(std::string_view name) const {
  for (std::size_t i = 0; i < buses_.size(); ++i)
    if (config_.buses[i].name == name) return buses_[i]->black_box;
  return nullptr;
}

std::vector<std::shared_ptr<BusScheduler>> Gateway::schedulers() const {
  std::vector<std::shared_ptr<BusScheduler>> schedulers;
  for (const auto& bus : buses_) schedulers.push_back(scheduler_of(bus));
  return schedulers;
}

std::vector<UnitMap> Gateway::unit_maps() const {
  std::vector<UnitMap> units;
  for (const auto& s : sensors_) {
    const std::uint16_t listener = listener_of(config_, s->config);
    units.push_back({s->config.unit_id, s->config.name, s->config.model, &s->map,
                     config_.server.word_order,
                     listener == kMainListener ? config_.server.port : listener, {}});
  }
  return units;
}

}  // namespace tiltgate
