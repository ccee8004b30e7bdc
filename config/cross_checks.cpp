#include "config/cross_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <span>

#include "config/listeners.h"
#include "device_server/port_url.h"

namespace tiltgate::config {

using toml_input::ErrorList;

namespace {

// `bus "line1" (line 4)`, or `bus[0] (line 4)` when its name is itself in error.
template <class Parsed>
std::string describe(const Parsed& parsed, std::string_view kind) {
  const int line = parsed.where.header().line;
  if (parsed.where.valid("name"))
    return fmt::format("{} \"{}\" (line {})", kind, parsed.config.name, line);
  return fmt::format("{} (line {})", parsed.where.path(), line);
}

template <class Parsed>
void reject_duplicate_names(const std::vector<Parsed>& items, std::string_view kind,
                            ErrorList& errors) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (!items[i].where.valid("name")) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (!items[j].where.valid("name") || items[j].config.name != items[i].config.name) continue;
      items[i].where.report(errors, "name",
                            fmt::format("duplicate {} name \"{}\", first declared at line {}", kind,
                                        items[i].config.name, items[j].where.header().line));
      break;
    }
  }
}

// The port as written, parsed again (read_bus reported it when it was in error).
std::optional<PortAddress> port_of(const ParsedBus& bus) {
  if (!bus.where.valid("port")) return std::nullopt;
  auto port = parse_port(bus.config.port);
  if (!port) return std::nullopt;
  return *port;
}

// The same device under two names (/dev/serial/by-id/... and /dev/ttyUSB0) is still one line;
// only ttys that exist right now can be resolved. A device server's port names no local file.
std::optional<std::filesystem::path> resolve_tty(const std::optional<PortAddress>& port) {
  if (!port || port->over_network()) return std::nullopt;
  std::error_code error;
  auto path = std::filesystem::canonical(port->path, error);
  if (error) return std::nullopt;
  return path;
}

// A device server's port, as two buses could both name it: its host (names and addresses
// compare without case) and its TCP port, whichever scheme reaches it.
std::optional<std::string> endpoint_of(const std::optional<PortAddress>& port) {
  if (!port || !port->over_network()) return std::nullopt;
  std::string endpoint = port->endpoint();
  std::transform(endpoint.begin(), endpoint.end(), endpoint.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return endpoint;
}

// What makes bus i's port the one bus j already uses, or nothing.
std::optional<std::string> shared_port(const std::vector<ParsedBus>& buses, std::size_t i,
                                       std::size_t j,
                                       const std::vector<std::optional<PortAddress>>& ports,
                                       const std::vector<std::optional<std::filesystem::path>>& devices) {
  const std::string& port = buses[i].config.port;
  if (port == buses[j].config.port)
    return fmt::format("\"{}\" is already used by {}", port, describe(buses[j], "bus"));
  // Servers often take one client per port, and two buses on one line would talk over each
  // other: one connection per bus.
  const std::optional<std::string> endpoint = endpoint_of(ports[i]);
  if (endpoint && endpoint == endpoint_of(ports[j]))
    return fmt::format("\"{}\": the device server {} is already used by {} (\"{}\")", port,
                       *endpoint, describe(buses[j], "bus"), buses[j].config.port);
  if (devices[i] && devices[j] && *devices[i] == *devices[j])
    return fmt::format("\"{}\" is {}, the same device as the port \"{}\" of {}", port,
                       devices[i]->string(), buses[j].config.port, describe(buses[j], "bus"));
  return std::nullopt;
}

void reject_shared_ports(const std::vector<ParsedBus>& buses, ErrorList& errors) {
  std::vector<std::optional<PortAddress>> ports;
  std::vector<std::optional<std::filesystem::path>> devices;
  for (const ParsedBus& bus : buses) {
    ports.push_back(port_of(bus));
    devices.push_back(resolve_tty(ports.back()));
  }
  for (std::size_t i = 0; i < buses.size(); ++i) {
    if (!ports[i]) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (!ports[j]) continue;
      if (auto shared = shared_port(buses, i, j, ports, devices)) {
        buses[i].where.report(errors, "port", std::move(*shared));
        break;
      }
    }
  }
}

const ParsedBus* find_bus(const std::vector<ParsedBus>& buses, const std::string& name) {
  for (const ParsedBus& bus : buses)
    if (bus.where.valid("name") && bus.config.name == name) return &bus;
  return nullptr;
}

// A model fits a bus whose protocol is one of its own family's.
bool model_fits(const ModelEntry& model, const ProtocolEntry& protocol) {
  return model.family == nullptr ||
         (model.family == protocol.family && model.model->speaks(protocol.protocol->name));
}

// The protocols a model's sensors speak: its own list, else its family's.
std::string protocols_of(const ModelEntry& model) {
  std::vector<std::string_view> names;
  for (const ProtocolDescriptor& protocol : model.family->protocols)
    if (model.model->speaks(protocol.name)) names.push_back(protocol.name);
  return or_list(names);
}

void report_unknown_bus(const ParsedSensor& sensor, const std::vector<ParsedBus>& buses,
                        ErrorList& errors) {
  std::vector<std::string> names;
  for (const ParsedBus& bus : buses)
    if (bus.where.valid("name")) names.push_back(bus.config.name);
  sensor.where.report(
      errors, "bus",
      names.empty() ? fmt::format("unknown bus \"{}\": no [[bus]] is defined", sensor.config.bus)
                    : fmt::format("unknown bus \"{}\", expected one of: {}", sensor.config.bus,
                                  fmt::join(names, ", ")));
}

// The address against its bus: the protocol's range, the master, and the sensors declared
// before it (`earlier`).
void check_address(const ParsedSensor& sensor, const ParsedBus& bus,
                   const ProtocolDescriptor& protocol, std::span<const ParsedSensor> earlier,
                   ErrorList& errors) {
  if (!sensor.where.valid("address")) return;
  const auto [min, max] = protocol.addresses;
  if (sensor.address < min || sensor.address > max) {
    return sensor.where.report(errors, "address",
                               fmt::format("{} is out of range for a {} bus, expected {}..{}",
                                           sensor.address, protocol.name, min, max));
  }
  // Where the master has an address, it is reserved for it.
  if (protocol.master_addresses && bus.where.usable("master_address") &&
      sensor.address == bus.config.master_address) {
    return sensor.where.report(errors, "address",
                               fmt::format("{} is the master_address of bus \"{}\"; a sensor "
                                           "needs an address of its own",
                                           sensor.address, bus.config.name));
  }
  for (const ParsedSensor& other : earlier) {
    if (other.where.valid("bus") && other.config.bus == sensor.config.bus &&
        other.where.valid("address") && other.address == sensor.address) {
      return sensor.where.report(
          errors, "address",
          fmt::format("{} is already used on bus \"{}\" by {}", sensor.address, sensor.config.bus,
                      describe(other, "sensor")));
    }
  }
}

void check_against_bus(const ParsedSensor& sensor, std::span<const ParsedSensor> earlier,
                       const std::vector<ParsedBus>& buses, ErrorList& errors,
                       FamilyList families) {
  if (!sensor.where.valid("bus")) return;
  const ParsedBus* bus = find_bus(buses, sensor.config.bus);
  if (bus == nullptr) return report_unknown_bus(sensor, buses, errors);
  if (!bus->where.usable("protocol")) return;
  const ProtocolEntry protocol = find_protocol(families, bus->config.protocol);
  if (protocol.protocol == nullptr) return;
  const ModelEntry model = find_model(families, sensor.config.model);
  if (sensor.where.valid("model") && !model_fits(model, protocol)) {
    sensor.where.report(
        errors, "model",
        fmt::format("model \"{}\" needs a {} bus, but bus \"{}\" is {}", sensor.config.model,
                    protocols_of(model), bus->config.name, bus->config.protocol));
  }
  check_address(sensor, *bus, *protocol.protocol, earlier, errors);
}

// Unit ids are unique among the units one listener serves ([[bus]] tcp_port).
void reject_duplicate_unit_ids(const std::vector<ParsedSensor>& sensors,
                               const std::vector<ParsedBus>& buses, ErrorList& errors) {
  std::vector<std::uint16_t> listeners;
  for (const ParsedSensor& sensor : sensors)
    listeners.push_back(listener_of_bus(buses, sensor.config.bus));
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    if (!sensors[i].where.valid("unit_id")) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (!sensors[j].where.valid("unit_id") ||
          sensors[j].config.unit_id != sensors[i].config.unit_id || listeners[j] != listeners[i])
        continue;
      sensors[i].where.report(
          errors, "unit_id",
          fmt::format("unit id {} is already used by {}{}", sensors[i].config.unit_id,
                      describe(sensors[j], "sensor"), on_listener(listeners[i])));
      break;
    }
  }
}

}  // namespace

void check_buses(const std::vector<ParsedBus>& buses, ErrorList& errors) {
  reject_duplicate_names(buses, "bus", errors);
  reject_shared_ports(buses, errors);
}

void check_sensors(const std::vector<ParsedSensor>& sensors, const std::vector<ParsedBus>& buses,
                   ErrorList& errors, FamilyList families) {
  reject_duplicate_names(sensors, "sensor", errors);
  reject_duplicate_unit_ids(sensors, buses, errors);
  const std::span<const ParsedSensor> all(sensors);
  for (std::size_t i = 0; i < sensors.size(); ++i)
    check_against_bus(sensors[i], all.first(i), buses, errors, families);
}

void check_feeds(const MqttConfig& mqtt, const SparkplugConfig& sparkplug,
                 toml_input::Place sparkplug_at, ErrorList& errors) {
  if (!mqtt.enabled || mqtt.client_id != sparkplug.client_id) return;
  if (mqtt.host != sparkplug.host || mqtt.port != sparkplug.port) return;
  errors.add(sparkplug_at, "sparkplug.client_id",
             fmt::format("\"{}\" is [mqtt]'s client_id on the same broker, expected another: "
                         "the broker would disconnect one client for the other",
                         sparkplug.client_id));
}

}  // namespace tiltgate::config
