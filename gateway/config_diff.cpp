#include "gateway/config_diff.h"

#include <algorithm>
#include <fmt/format.h>

namespace tiltgate {

namespace {

template <class Item>
const Item* find_named(const std::vector<Item>& items, const std::string& name) {
  auto it = std::find_if(items.begin(), items.end(),
                         [&](const Item& item) { return item.name == name; });
  return it == items.end() ? nullptr : &*it;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string listed(const std::vector<std::string>& names) {
  return names.empty() ? std::string("-") : fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

bool same_settings(const BusConfig& a, const BusConfig& b) {
  BusConfig anywhere = b;
  anywhere.line = a.line;
  // Which TCP port serves its units is routing, not the line: a moved port keeps the tty open.
  anywhere.tcp_port = a.tcp_port;
  return a == anywhere;
}

bool same_settings(const SensorConfig& a, const SensorConfig& b) {
  SensorConfig anywhere = b;
  anywhere.line = a.line;
  return a == anywhere;
}

ConfigDiff diff_configs(const Config& running, const Config& loaded) {
  ConfigDiff diff;
  for (const BusConfig& bus : loaded.buses) {
    const BusConfig* before = find_named(running.buses, bus.name);
    if (before == nullptr)
      diff.buses_added.push_back(bus.name);
    else if (same_settings(*before, bus))
      diff.buses_kept.push_back(bus.name);
    else
      diff.buses_reopened.push_back(bus.name);
  }
  for (const BusConfig& bus : running.buses)
    if (find_named(loaded.buses, bus.name) == nullptr) diff.buses_removed.push_back(bus.name);

  for (const SensorConfig& sensor : loaded.sensors) {
    const SensorConfig* before = find_named(running.sensors, sensor.name);
    if (before == nullptr)
      diff.sensors_added.push_back(sensor.name);
    else if (same_settings(*before, sensor) && contains(diff.buses_kept, sensor.bus))
      diff.sensors_kept.push_back(sensor.name);
    else
      diff.sensors_changed.push_back(sensor.name);
  }
  for (const SensorConfig& sensor : running.sensors)
    if (find_named(loaded.sensors, sensor.name) == nullptr)
      diff.sensors_removed.push_back(sensor.name);

  diff.server_changed = !(running.server == loaded.server);
  diff.server_listener_changed = running.server.listen != loaded.server.listen ||
                                 running.server.port != loaded.server.port;
  diff.control_socket_changed = running.server.control_socket != loaded.server.control_socket;
  diff.http_changed = !(running.http == loaded.http);
  diff.mqtt_changed = !(running.mqtt == loaded.mqtt);
  diff.sparkplug_changed = !(running.sparkplug == loaded.sparkplug);
  return diff;
}

std::string summarize(const ConfigDiff& diff) {
  return fmt::format(
      "buses kept: {}; reopened: {}; added: {}; removed: {}. sensors kept: {}; changed: {}; "
      "added: {}; removed: {}",
      listed(diff.buses_kept), listed(diff.buses_reopened), listed(diff.buses_added),
      listed(diff.buses_removed), listed(diff.sensors_kept), listed(diff.sensors_changed),
      listed(diff.sensors_added), listed(diff.sensors_removed));
}

std::string describe_changes(const Config& running, const Config& loaded) {
  const ConfigDiff diff = diff_configs(running, loaded);
  std::vector<std::string> sections;
  if (diff.server_changed) sections.emplace_back("server");
  if (diff.http_changed) sections.emplace_back("http");
  if (diff.mqtt_changed) sections.emplace_back("mqtt");
  if (diff.sparkplug_changed) sections.emplace_back("sparkplug");
  if (running.aggregates != loaded.aggregates) sections.emplace_back("aggregate");
  std::string text =
      fmt::format("{}. sections changed: {}", summarize(diff), listed(sections));
  const auto door = [&](std::string_view name, const std::string& listen_before,
                        unsigned port_before, const std::string& listen_after, unsigned port_after) {
    if (listen_before != listen_after || port_before != port_after)
      text += fmt::format(". [{}] {}:{} -> {}:{}", name, listen_before, port_before, listen_after,
                          port_after);
  };
  door("server", running.server.listen, running.server.port, loaded.server.listen,
       loaded.server.port);
  door("http", running.http.listen, running.http.port, loaded.http.listen, loaded.http.port);
  if (running.http.enabled != loaded.http.enabled)
    text += loaded.http.enabled ? ". [http] enabled" : ". [http] disabled";
  return text;
}

}  // namespace tiltgate
