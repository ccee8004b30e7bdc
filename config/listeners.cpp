#include "config/listeners.h"

#include <fmt/format.h>

namespace tiltgate {

std::uint16_t listener_of(const Config& config, const SensorConfig& sensor) {
  for (const BusConfig& bus : config.buses)
    if (bus.name == sensor.bus) return listener_of(bus);
  return kMainListener;
}

std::uint16_t listener_of(const Config& config, const AggregateConfig& aggregate) {
  for (const SensorConfig& sensor : config.sensors)
    if (!aggregate.sensors.empty() && sensor.name == aggregate.sensors.front())
      return listener_of(config, sensor);
  for (const BusConfig& bus : config.buses)
    if (bus.name == aggregate.bus) return listener_of(bus);
  return kMainListener;
}

}  // namespace tiltgate

namespace tiltgate::config {

using toml_input::ErrorList;

std::uint16_t listener_of_bus(const std::vector<ParsedBus>& buses, const std::string& bus) {
  for (const ParsedBus& parsed : buses)
    if (parsed.where.valid("name") && parsed.config.name == bus) return listener_of(parsed.config);
  return kMainListener;
}

std::string describe_listener(std::uint16_t listener) {
  return listener == kMainListener ? std::string("the main port ([server] port)")
                                   : fmt::format("port {}", listener);
}

std::string on_listener(std::uint16_t listener) {
  return listener == kMainListener ? std::string() : fmt::format(" on port {}", listener);
}

void check_tcp_ports(const std::vector<ParsedBus>& buses, const ServerConfig& server,
                     ErrorList& errors) {
  for (std::size_t i = 0; i < buses.size(); ++i) {
    const ParsedBus& bus = buses[i];
    if (!bus.config.tcp_port || !bus.where.valid("tcp_port")) continue;
    const std::uint16_t port = *bus.config.tcp_port;
    if (!server.plain_tcp) {
      bus.where.report(errors, "tcp_port",
                       "a bus's own listener is plain Modbus TCP, but [server] plain_tcp = false "
                       "(TLS only); leave tcp_port out or allow plain TCP");
      continue;
    }
    if (port == server.port) {
      bus.where.report(errors, "tcp_port",
                       fmt::format("{} is [server] port; a bus's own port must be another one",
                                   port));
      continue;
    }
    if (server.tls && port == server.tls->port) {
      bus.where.report(errors, "tcp_port",
                       fmt::format("{} is the port of [server] tls; a bus's own port must be "
                                   "another one",
                                   port));
      continue;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (buses[j].config.tcp_port != bus.config.tcp_port) continue;
      bus.where.report(errors, "tcp_port",
                       fmt::format("{} is already the tcp_port of bus \"{}\" (line {}); each "
                                   "bus's listener needs a port of its own",
                                   port, buses[j].config.name, buses[j].where.header().line));
      break;
    }
  }
}

}  // namespace tiltgate::config
