// Gateway::reload: a new configuration applied to the running gateway (SIGHUP), keeping what
// did not change. The difference is worked out by diff_configs (gateway/config_diff.h).
#include <algorithm>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gateway/config_diff.h"
#include "gateway/gateway.h"

namespace tiltgate {

namespace {

bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

template <class T>
std::shared_ptr<void> retired(std::unique_ptr<T> service) {
  return std::shared_ptr<void>(std::move(service));
}

}  // namespace

void Gateway::retire_bus_listeners(const Config& loaded) {
  std::vector<BusListener> kept;
  for (BusListener& listener : bus_listeners_) {
    const bool used = std::any_of(loaded.buses.begin(), loaded.buses.end(), [&](const auto& bus) {
      return listener_of(bus) == listener.port;
    });
    if (used) {
      listener.router->clear();
      kept.push_back(std::move(listener));
      continue;
    }
    // Its clients are closed; a request being answered still holds its router.
    listener.server->stop();
    spdlog::info("Modbus TCP port {} closed: no bus has it as tcp_port", listener.port);
    retired_services_.push_back(std::make_shared<BusListener>(std::move(listener)));
  }
  bus_listeners_ = std::move(kept);
}

void Gateway::start_or_apply_bus_listeners() {
  const RouterOptions options{config_.server.writes, config_.server.word_order,
                              config_.server.write_timeout};
  std::vector<BusListener> served;
  for (BusListener& listener : bus_listeners_) {
    listener.router->set_options(options);
    if (listener.server->local_port() != 0) {
      listener.server->apply(bus_listener_options(config_.server, listener.port));
      served.push_back(std::move(listener));
      continue;
    }
    if (auto started = listener.server->start(); !started) {
      spdlog::error("Modbus TCP port {} not served: {}", listener.port, started.error());
      listener.server->stop();
      retired_services_.push_back(std::make_shared<BusListener>(std::move(listener)));
      continue;
    }
    spdlog::info("Modbus TCP port {} opened", listener.port);
    served.push_back(std::move(listener));
  }
  bus_listeners_ = std::move(served);
}

void Gateway::reload(const Config& loaded) {
  const ConfigDiff diff = diff_configs(config_, loaded);
  if (loaded.server.threads != config_.server.threads)
    spdlog::warn("[server] threads applies at the next start; still {} thread(s)",
                 tcp_workers_->size());
  // From here on, what is made (bus listeners, their options) is made for the new file.
  config_ = loaded;

  // Every listener's units are routed anew; listeners whose port is gone stop, new ones are
  // made as their first unit is routed and started below. Requests see the new routes only
  // once all are made (commit_update() at the end).
  router_.begin_update();
  for (BusListener& listener : bus_listeners_) listener.router->begin_update();
  router_.clear();
  retire_bus_listeners(loaded);

  // Buses, in the new file's order: the unchanged ones as they are (tty open, scheduler and
  // queued writes untouched), the others made anew and started below.
  std::vector<Bus> old_buses = std::move(buses_);
  buses_.clear();
  std::vector<std::size_t> fresh_buses;
  for (const BusConfig& config : loaded.buses) {
    auto old = std::find_if(old_buses.begin(), old_buses.end(), [&](const Bus& bus) {
      return bus.scheduler && bus.scheduler->name() == config.name;
    });
    if (listed(diff.buses_kept, config.name) && old != old_buses.end()) {
      pass_through(config, *old->scheduler, false);
      buses_.push_back(std::move(*old));
      old->scheduler.reset();  // taken
    } else {
      buses_.push_back(make_bus(config));
      fresh_buses.push_back(buses_.size() - 1);
    }
  }
  // Removed and changed buses: no more polls; their queued writes finish, then the tty closes.
  for (Bus& bus : old_buses) {
    if (!bus.scheduler) continue;
    bus.scheduler->retire();
    retired_buses_.push_back(std::move(bus));
  }

  // Sensors, in the new file's order: unchanged ones keep their object (cache, written
  // registers, counters, history, queued writes); the others are made anew on their bus.
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
      router_for(listener_of(loaded, config)).add(*old);
      sensors_.push_back(std::move(*old));
      continue;
    }
    std::size_t bus = 0;
    while (bus < loaded.buses.size() && loaded.buses[bus].name != config.bus) ++bus;
    if (bus == loaded.buses.size()) continue;  // the loader rejects this
    if (auto sensor = make_sensor(config, loaded.buses[bus], *buses_[bus].scheduler))
      sensors_.push_back(std::move(sensor));
  }
  // Removed and replaced sensors leave their bus's polls (a retired bus has none left). Their
  // queued writes still run: each request being answered holds its sensor.
  for (const auto& sensor : old_sensors)
    if (sensor && sensor->bus != nullptr) sensor->bus->remove(*sensor);

  // Aggregates are rebuilt over the sensors served now (kept or new).
  make_aggregates();
  for (std::size_t index : fresh_buses) start_bus(buses_[index]);

  router_.set_options(RouterOptions{config_.server.writes, config_.server.word_order,
                                    config_.server.write_timeout});
  router_.commit_update();
  for (BusListener& listener : bus_listeners_) listener.router->commit_update();
  server_->apply(modbus_server_options(config_.server));
  start_or_apply_bus_listeners();

  std::vector<std::string> restarted;
  if (control_ || !config_.server.control_socket.empty()) {
    if (diff.control_socket_changed || !diff.buses_unchanged()) {
      // Its sessions hold the old buses: a command in progress is ended and reconnects.
      if (control_) {
        control_->stop();
        retired_services_.push_back(retired(std::move(control_)));
      }
      make_control();
      start_control();
      restarted.push_back("control socket");
    }
  }
  if (diff.http_changed) {
    if (http_) {
      http_->stop();
      retired_services_.push_back(retired(std::move(http_)));
    }
    std::unique_ptr<HistoryRecorder> previous = std::move(history_);
    make_http(previous.get());
    start_http();
    restarted.push_back("http");
  } else if (history_ && !diff.sensors_unchanged()) {
    std::unique_ptr<HistoryRecorder> previous = std::move(history_);
    make_history(previous.get());
  }
  if (diff.mqtt_changed) {
    if (mqtt_) {
      mqtt_->stop();
      retired_services_.push_back(retired(std::move(mqtt_)));
    }
    make_mqtt();
    start_mqtt();
    restarted.push_back("mqtt");
  }
  if (!diff.buses_unchanged() || !diff.sensors_unchanged()) {
    // The rates are kept per position; positions moved.
    sensor_poll_rates_ = CounterRates{};
    bus_rates_ = CounterRates{};
  }
  loaded_at_ = local_time_now();
  spdlog::info("configuration reloaded from {}: {}{}{}", config_.path, summarize(diff),
               restarted.empty() ? "" : ". restarted: ", fmt::join(restarted, ", "));
}

}  // namespace tiltgate
