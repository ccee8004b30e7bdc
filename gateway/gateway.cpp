#include "gateway/gateway.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "driver/family.h"
#include "gateway/driver_registry.h"
#include "mapping/map_definition.h"

namespace tiltgate {

namespace asio = boost::asio;

RegisterMap map_for(const SensorConfig& sensor) {
  return build_map(sensor.map, sensor.model, sensor.family_options.device_values());
}

Gateway::Gateway(boost::asio::io_context& io, const Config& config)
    : io_(io),
      config_(config),
      router_(RouterOptions{config.server.writes, config.server.word_order,
                            config.server.write_timeout}),
      history_timer_(io.get_executor()),
      sample_timer_(io.get_executor()) {
  for (const BusConfig& bus : config_.buses) {
    Bus b;
    SerialLineOptions options = serial_options_from(bus);
    options.exclusive = true;
    b.line = std::make_unique<SerialLine>(io_.get_executor(), options);
    b.scheduler = std::make_unique<BusScheduler>(io_.get_executor(), *b.line, bus.name);
    pass_through(bus, *b.scheduler);
    buses_.push_back(std::move(b));
  }
  for (const SensorConfig& sc : config_.sensors) {
    std::size_t bus_index = 0;
    while (bus_index < config_.buses.size() && config_.buses[bus_index].name != sc.bus) ++bus_index;
    if (bus_index == config_.buses.size()) continue;  // the loader rejects this
    auto sensor = std::make_unique<GatewaySensor>();
    sensor->config = sc;
    sensor->driver = make_driver(sc, config_.buses[bus_index]);
    if (!sensor->driver) continue;  // the loader rejects unknown models
    sensor->map = map_for(sc);
    sensor->written.assign(sensor->map.holding_end(), 0);
    sensor->stale_after = sc.stale_after.value_or(default_stale_after(sc.poll));
    buses_[bus_index].scheduler->add(*sensor);
    router_.add(*sensor);
    sensors_.push_back(std::move(sensor));
  }
  ModbusServerOptions options;
  options.listen = config_.server.listen;
  options.port = config_.server.port;
  options.max_clients = config_.server.max_clients;
  options.max_clients_per_host = config_.server.max_clients_per_host;
  options.allow = config_.server.allow;
  options.write_allow = config_.server.write_allow;
  options.plain_tcp = config_.server.plain_tcp;
  if (const auto& tls = config_.server.tls)
    options.tls = ModbusTlsOptions{tls->cert_pem, tls->key_pem, tls->ca_pem,
                                   tls->cert_file, tls->key_file, tls->ca_file, tls->port};
  options.idle_timeout = config_.server.idle_timeout;
  options.request_timeout = config_.server.request_timeout;
  server_ = std::make_unique<ModbusTcpServer>(io_.get_executor(), router_, options);
  if (!config_.server.control_socket.empty()) {
    std::vector<ControlServer::ServedBus> served;
    for (std::size_t i = 0; i < buses_.size(); ++i)
      served.push_back({config_.buses[i], buses_[i].scheduler.get()});
    control_ = std::make_unique<ControlServer>(io_.get_executor(), config_.server.control_socket,
                                               std::move(served));
  }
  start_seconds_ = std::chrono::duration<double>(
                       std::chrono::system_clock::now().time_since_epoch()).count();
  if (config_.http.enabled) {
    HttpServerOptions http;
    http.listen = config_.http.listen;
    http.port = config_.http.port;
    http.allow = config_.http.allow;
    std::vector<std::string> names;
    for (const auto& sensor : sensors_) names.push_back(sensor->config.name);
    history_ = std::make_unique<HistoryRecorder>(
        std::move(names), std::size_t(std::chrono::milliseconds(config_.http.history_seconds) /
                                      config_.http.history_interval));
    http_ = std::make_unique<HttpServer>(
        io_.get_executor(), [this] { return status(SteadyClock::now()); }, http,
        [this](std::string_view sensor) { return history_->history(sensor); });
  }
  if (config_.mqtt.enabled)
    mqtt_ = std::make_unique<MqttFeed>(
        io_.get_executor(), [this] { return status(SteadyClock::now()); }, config_.mqtt);
}

Gateway::~Gateway() = default;

void Gateway::pass_through(const BusConfig& bus, BusScheduler& scheduler) {
  if (bus.pass_through.empty()) return;
  const ProtocolEntry protocol = find_protocol(registered_families(), bus.protocol);
  if (protocol.protocol == nullptr || protocol.protocol->forward == nullptr) return;  // refused
  scheduler.enable_forwarding(protocol.protocol->forward);
  for (std::uint8_t unit_id : bus.pass_through) router_.pass_through(unit_id, scheduler);
  spdlog::info("bus {}: unit id(s) {} passed through", bus.name,
               fmt::join(bus.pass_through, ", "));
}

Expected<Done, std::string> Gateway::start() {
  auto listening = server_->start();
  if (!listening) return Unexpected(listening.error());
  for (Bus& bus : buses_) {
    bus.line->start();
    boost::asio::co_spawn(io_, bus.scheduler->run(), boost::asio::detached);
  }
  if (control_) {
    if (auto control = control_->start(); !control)
      spdlog::warn("control socket off: {}; commissioning commands cannot use this gateway's "
                   "buses",
                   control.error());
    else
      spdlog::info("control socket {}", control_->path());
  }
  if (http_) {
    if (auto http = http_->start(); !http)
      spdlog::warn("HTTP status API off: {}", http.error());
    else
      spdlog::info("HTTP status API and metrics on http://{}:{}/", config_.http.listen,
                   http_->local_port());
    boost::asio::co_spawn(io_, record_history(), boost::asio::detached);
  }
  if (mqtt_) {
    if (auto mqtt = mqtt_->start(); !mqtt)
      spdlog::warn("MQTT feed off: {}", mqtt.error());
    else
      spdlog::info("MQTT feed to {}:{} under {}/", config_.mqtt.host, config_.mqtt.port,
                   config_.mqtt.topic_prefix);
  }
  boost::asio::co_spawn(io_, sample_counters(), boost::asio::detached);
  spdlog::info("serving {} sensor(s) on {} bus(es), Modbus TCP {}:{}{}", sensors_.size(),
               buses_.size(), config_.server.listen, server_->local_port(),
               config_.server.writes ? ", writes enabled" : "");
  return Done{};
}

boost::asio::awaitable<void> Gateway::record_history() {
  const auto interval = config_.http.history_interval;
  auto next = SteadyClock::now() + interval;
  while (!stopping_) {
    history_timer_.expires_at(next);
    boost::system::error_code ec;
    co_await history_timer_.async_wait(
        boost::asio::redirect_error(boost::asio::use_awaitable, ec));
    if (ec || stopping_) co_return;
    const auto now = SteadyClock::now();
    const auto unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
    history_->record(status(now), unix_ms);
    // A steady cadence; after a stall (a suspended machine) start over rather than catch up.
    next += interval;
    if (next < now) next = now + interval;
  }
}

void Gateway::stop() {
  stopping_ = true;
  sample_timer_.cancel();
  history_timer_.cancel();
  server_->stop();
  if (control_) control_->stop();
  if (http_) http_->stop();
  if (mqtt_) mqtt_->stop();
  for (Bus& bus : buses_) {
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
    units.push_back({s->config.unit_id, s->config.name, s->config.model, &s->map,
                     config_.server.word_order});
  }
  return units;
}

}  // namespace tiltgate
