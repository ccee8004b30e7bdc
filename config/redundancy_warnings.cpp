#include "config/redundancy_warnings.h"

#include <fmt/format.h>

#include <algorithm>

#include "device_server/port_url.h"

namespace tiltgate {

namespace {

bool has_sensors(const Config& config, const BusConfig& bus) {
  return std::any_of(config.sensors.begin(), config.sensors.end(),
                     [&](const SensorConfig& sensor) { return sensor.bus == bus.name; });
}

// A device server takes one client per port, and Modbus TCP devices answer the connection that
// asked: either way a second gateway has nothing to listen to.
std::string unheard_bus(const BusConfig& bus, const ProtocolEntry& protocol) {
  if (protocol.protocol != nullptr && protocol.protocol->devices_speak_tcp)
    return fmt::format("bus \"{}\" reaches its devices over TCP (\"{}\"): a standby cannot "
                       "listen to it; it connects only when it takes over",
                       bus.name, bus.port);
  return fmt::format("bus \"{}\" is behind a device server (\"{}\"): a standby cannot listen "
                     "to it; it opens it only when it takes over",
                     bus.name, bus.port);
}

}  // namespace

std::vector<std::string> redundancy_warnings(const Config& config, FamilyList families) {
  std::vector<std::string> warnings;
  if (!config.redundancy.enabled()) return warnings;
  for (const BusConfig& bus : config.buses) {
    const ProtocolEntry protocol = find_protocol(families, bus.protocol);
    const auto port = parse_port(bus.port);
    if (port && port->over_network()) {
      warnings.push_back(unheard_bus(bus, protocol));
      continue;
    }
    // Pass-through requests come when a client asks, not on a schedule.
    if (!has_sensors(config, bus))
      warnings.push_back(fmt::format(
          "bus \"{}\" has no sensors (pass-through only): it carries no regular requests, so a "
          "standby cannot tell from it that the primary is alive",
          bus.name));
    // A receive-only port cannot see the ninth bit (docs/diagnostics.md, "Listening only").
    if (protocol.protocol != nullptr && protocol.protocol->framing == Framing::nine_bit)
      warnings.push_back(fmt::format(
          "bus \"{}\" is {}: a standby hears its address bytes without their 9th bit; it still "
          "follows the line, telling requests from replies by their form, with no checksum to "
          "confirm them (docs/diagnostics.md, \"Listening only\")",
          bus.name, bus.protocol));
  }
  return warnings;
}

}  // namespace tiltgate
