#include "gateway/gateway.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <ctime>
#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "driver/family.h"
#include "gateway/driver_registry.h"
#include "mapping/map_definition.h"

namespace tiltgate {

namespace asio = boost::asio;

void finish_stopped(boost::asio::io_context& io) {
  io.restart();
  io.run_for(std::chrono::seconds(2));
}

RegisterMap map_for(const SensorConfig& sensor) {
  return build_map(sensor.map, sensor.model, sensor.family_options.device_values());
}

ModbusServerOptions modbus_server_options(const ServerConfig& server) {
  ModbusServerOptions options;
  options.listen = server.listen;
  options.port = server.port;
  options.max_clients = server.max_clients;
  options.max_clients_per_host = server.max_clients_per_host;
  options.allow = server.allow;
  options.write_allow = server.write_allow;
  options.plain_tcp = server.plain_tcp;
  if (const auto& tls = server.tls)
    options.tls = ModbusTlsOptions{tls->cert_pem, tls->key_pem, tls->ca_pem,
                                   tls->cert_file, tls->key_file, tls->ca_file, tls->port};
  options.idle_timeout = server.idle_timeout;
  options.request_timeout = server.request_timeout;
  return options;
}

ModbusServerOptions bus_listener_options(const ServerConfig& server, std::uint16_t port) {
  ModbusServerOptions options = modbus_server_options(server);
  options.port = port;
  options.plain_tcp = true;
  options.tls.reset();
  return options;
}

std::string Gateway::local_time_now() {
  return fmt::format("{:%Y-%m-%d %H:%M:%S}", fmt::localtime(std::time(nullptr)));
}

Gateway::Gateway(boost::asio::io_context& io, const Config& config)
    : io_(io),
      config_(config),
      tcp_workers_(std::make_unique<TcpWorkerPool>(
          config.server.threads > 0 ? std::size_t(config.server.threads) : default_tcp_threads())),
      router_(io.get_executor(), RouterOptions{config.server.writes, config.server.word_order,
                                               config.server.write_timeout}),
      history_timer_(io.get_executor()),
      sample_timer_(io.get_executor()) {
  for (const BusConfig& bus : config_.buses) buses_.push_back(make_bus(bus));
  for (const SensorConfig& sc : config_.sensors) {
    std::size_t bus_index = 0;
    while (bus_index < config_.buses.size() && config_.buses[bus_index].name != sc.bus) ++bus_index;
    if (bus_index == config_.buses.size()) continue;  // the loader rejects this
    auto sensor = make_sensor(sc, config_.buses[bus_index], *buses_[bus_index].scheduler);
    if (sensor) sensors_.push_back(std::move(sensor));
  }
  make_aggregates();
  server_ = std::make_unique<ModbusTcpServer>(io_.get_executor(), router_,
                                              modbus_server_options(config_.server),
                                              tcp_workers_.get());
  start_seconds_ = std::chrono::duration<double>(
                       std::chrono::system_clock::now().time_since_epoch()).count();
  loaded_at_ = local_time_now();
  make_control();
  make_http(nullptr);
  make_mqtt();
}

Gateway::~Gateway() {
  // The connections' threads end first: their coroutines refer to the servers and routers.
  tcp_workers_->stop();
}

Gateway::Bus Gateway::make_bus(const BusConfig& config) {
  Bus bus;
  SerialLineOptions options = serial_options_from(config);
  options.exclusive = true;
  bus.line = std::make_unique<SerialLine>(io_.get_executor(), options);
  bus.scheduler = std::make_unique<BusScheduler>(io_.get_executor(), *bus.line, config.name);
  pass_through(config, *bus.scheduler, true);
  return bus;
}

std::shared_ptr<GatewaySensor> Gateway::make_sensor(const SensorConfig& config,
                                                    const BusConfig& bus_config,
                                                    BusScheduler& bus) {
  auto sensor = std::make_shared<GatewaySensor>();
  sensor->config = config;
  sensor->driver = make_driver(config, bus_config);
  if (!sensor->driver) return nullptr;  // the loader rejects unknown models
  sensor->map = map_for(config);
  sensor->written.assign(sensor->map.holding_end(), 0);
  sensor->stale_after = config.stale_after.value_or(default_stale_after(config.poll));
  bus.add(sensor);
  router_for(listener_of(bus_config)).add(sensor);
  return sensor;
}

RequestRouter& Gateway::router_for(std::uint16_t listener) {
  if (listener == kMainListener) return router_;
  for (BusListener& bus : bus_listeners_)
    if (bus.port == listener) return *bus.router;
  BusListener made;
  made.port = listener;
  made.router = std::make_unique<RequestRouter>(
      io_.get_executor(),
      RouterOptions{config_.server.writes, config_.server.word_order, config_.server.write_timeout});
  made.server = std::make_unique<ModbusTcpServer>(io_.get_executor(), *made.router,
                                                  bus_listener_options(config_.server, listener),
                                                  tcp_workers_.get());
  bus_listeners_.push_back(std::move(made));
  return *bus_listeners_.back().router;
}

void Gateway::make_aggregates() {
  for (const AggregateConfig& config : config_.aggregates) {
    auto aggregate = make_gateway_aggregate(config, sensors_);
    if (!aggregate) {
      spdlog::error("aggregate unit {} (line {}) not served: {}", config.unit_id, config.line,
                    aggregate.error());
      continue;
    }
    router_for(listener_of(config_, config)).add(std::move(*aggregate));
  }
}

std::vector<const ModbusTcpServer*> Gateway::servers() const {
  std::vector<const ModbusTcpServer*> all{server_.get()};
  for (const BusListener& bus : bus_listeners_) all.push_back(bus.server.get());
  return all;
}

std::vector<std::uint16_t> Gateway::bus_ports() const {
  std::vector<std::uint16_t> ports;
  for (const BusListener& bus : bus_listeners_) ports.push_back(bus.server->local_port());
  return ports;
}

void Gateway::make_control() {
  if (config_.server.control_socket.empty()) return;
  std::vector<ControlServer::ServedBus> served;
  for (std::size_t i = 0; i < buses_.size(); ++i)
    served.push_back({config_.buses[i], buses_[i].scheduler.get()});
  control_ = std::make_unique<ControlServer>(io_.get_executor(), config_.server.control_socket,
                                             std::move(served));
}

void Gateway::make_http(const HistoryRecorder* previous) {
  if (!config_.http.enabled) return;
  HttpServerOptions http;
  http.listen = config_.http.listen;
  http.port = config_.http.port;
  http.allow = config_.http.allow;
  make_history(previous);
  http_ = std::make_unique<HttpServer>(
      io_.get_executor(), [this] { return status(SteadyClock::now()); }, http,
      [this](std::string_view sensor) -> std::optional<std::vector<AngleSample>> {
        if (!history_) return std::nullopt;  // a reload turned [http] off meanwhile
        return history_->history(sensor);
      });
}

void Gateway::make_history(const HistoryRecorder* previous) {
  std::vector<std::string> names;
  for (const auto& sensor : sensors_) names.push_back(sensor->config.name);
  history_ = std::make_unique<HistoryRecorder>(
      std::move(names), std::size_t(std::chrono::milliseconds(config_.http.history_seconds) /
                                    config_.http.history_interval));
  if (previous != nullptr) history_->carry_over(*previous);
}

void Gateway::make_mqtt() {
  if (!config_.mqtt.enabled) return;
  mqtt_ = std::make_unique<MqttFeed>(
      io_.get_executor(), [this] { return status(SteadyClock::now()); }, config_.mqtt);
}

void Gateway::pass_through(const BusConfig& bus, BusScheduler& scheduler, bool announce) {
  if (bus.pass_through.empty()) return;
  const ProtocolEntry protocol = find_protocol(registered_families(), bus.protocol);
  if (protocol.protocol == nullptr || protocol.protocol->forward == nullptr) return;  // refused
  scheduler.enable_forwarding(protocol.protocol->forward);
  RequestRouter& router = router_for(listener_of(bus));
  for (std::uint8_t unit_id : bus.pass_through) router.pass_through(unit_id, scheduler);
  if (announce)
    spdlog::info("bus {}: unit id(s) {} passed through", bus.name,
                 fmt::join(bus.pass_through, ", "));
}

Expected<Done, std::string> Gateway::start() {
  auto listening = server_->start();
  if (!listening) return Unexpected(listening.error());
  for (BusListener& bus : bus_listeners_) {
    auto bus_listening = bus.server->start();
    if (!bus_listening) return Unexpected(bus_listening.error());
  }
  for (Bus& bus : buses_) start_bus(bus);
  start_control();
  start_http();
  start_mqtt();
  boost::asio::co_spawn(io_, record_history(), boost::asio::detached);
  boost::asio::co_spawn(io_, sample_counters(), boost::asio::detached);
  spdlog::info("serving {} sensor(s) on {} bus(es), Modbus TCP {}:{} ({} thread(s)){}",
               sensors_.size(), buses_.size(), config_.server.listen, server_->local_port(),
               tcp_workers_->size(), config_.server.writes ? ", writes enabled" : "");
  for (const BusConfig& bus : config_.buses)
    if (bus.tcp_port) spdlog::info("bus {}: its units on Modbus TCP port {}", bus.name, *bus.tcp_port);
  return Done{};
}

void Gateway::start_bus(Bus& bus) {
  bus.line->start();
  boost::asio::co_spawn(io_, run_bus(*bus.scheduler, *bus.line), boost::asio::detached);
}

boost::asio::awaitable<void> Gateway::run_bus(BusScheduler& scheduler, SerialLine& line) {
  co_await scheduler.run();
  // A bus a reload retired lets its tty go once its queued writes are done; at shutdown,
  // stop() closes every line itself.
  if (scheduler.retiring()) line.stop();
}

void Gateway::start_control() {
  if (!control_) return;
  if (auto control = control_->start(); !control)
    spdlog::warn("control socket off: {}; commissioning commands cannot use this gateway's "
                 "buses",
                 control.error());
  else
    spdlog::info("control socket {}", control_->path());
}

void Gateway::start_http() {
  if (!http_) return;
  if (auto http = http_->start(); !http)
    spdlog::warn("HTTP status API off: {}", http.error());
  else
    spdlog::info("HTTP status API and metrics on http://{}:{}/", config_.http.listen,
                 http_->local_port());
}

void Gateway::start_mqtt() {
  if (!mqtt_) return;
  if (auto mqtt = mqtt_->start(); !mqtt)
    spdlog::warn("MQTT feed off: {}", mqtt.error());
  else
    spdlog::info("MQTT feed to {}:{} under {}/", config_.mqtt.host, config_.mqtt.port,
                 config_.mqtt.topic_prefix);
}

boost::asio::awaitable<void> Gateway::record_history() {
  // Runs whether or not [http] is on: a reload may turn it on, or change the interval (which
  // applies from the next sample on).
  auto next = SteadyClock::now() + config_.http.history_interval;
  while (!stopping_) {
    const auto interval = config_.http.history_interval;
    history_timer_.expires_at(next);
    boost::system::error_code ec;
    co_await history_timer_.async_wait(
        boost::asio::redirect_error(boost::asio::use_awaitable, ec));
    if (ec || stopping_) co_return;
    const auto now = SteadyClock::now();
    const auto unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
    if (history_) history_->record(status(now), unix_ms);
    // A steady cadence; after a stall (a suspended machine) start over rather than catch up.
    next += interval;
    if (next < now) next = now + interval;
  }
}

void Gateway::stop() {
  stopping_ = true;
  sample_timer_.cancel();
  history_timer_.cancel();
  // Writes and forwarded requests still arriving are answered at once, not queued for buses
  // that stop below.
  router_.stop();
  for (BusListener& bus : bus_listeners_) bus.router->stop();
  server_->stop();
  for (BusListener& bus : bus_listeners_) bus.server->stop();
  if (control_) control_->stop();
  if (http_) http_->stop();
  if (mqtt_) mqtt_->stop();
  for (std::vector<Bus>* buses : {&buses_, &retired_buses_})
    for (Bus& bus : *buses) {
      bus.scheduler->stop();
      bus.line->stop();
    }
}

asio::awaitable<void> Gateway::sample_counters() {
  while (!stopping_) {
    record_counters(SteadyClock::now());
    sample_timer_.expires_after(std::chrono::seconds(1));
    boost::system::error_code ec;
    co_await sample_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

void Gateway::record_counters(SteadyClock::time_point now) {
  std::vector<double> polls;
  for (const auto& sensor : sensors_) {
    const SensorCounters& counters = sensor->driver->state().counters;
    polls.push_back(double(counters.polls_ok) + double(counters.polls_failed));
  }
  sensor_poll_rates_.record(now, std::move(polls));
  std::vector<double> buses;
  for (const Bus& bus : buses_) {
    const BusSchedulerStats& stats = bus.scheduler->stats();
    buses.push_back(double(stats.polls));
    buses.push_back(std::chrono::duration<double>(stats.busy).count());
  }
  bus_rates_.record(now, std::move(buses));
}

std::uint16_t Gateway::port() const { return server_->local_port(); }

std::uint16_t Gateway::http_port() const { return http_ ? http_->local_port() : 0; }

std::optional<MqttStats> Gateway::mqtt_stats() const {
  if (!mqtt_) return std::nullopt;
  return mqtt_->stats();
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
