#include "config/aggregate_checks.h"

#include <fmt/format.h>

#include <algorithm>

#include "config/listeners.h"
#include "mapping/aggregate_layout.h"

namespace tiltgate::config {

using toml_input::ErrorList;

namespace {

const ParsedSensor* find_sensor(const std::vector<ParsedSensor>& sensors,
                                const std::string& name) {
  for (const ParsedSensor& sensor : sensors)
    if (sensor.where.valid("name") && sensor.config.name == name) return &sensor;
  return nullptr;
}

bool bus_exists(const std::vector<ParsedBus>& buses, const std::string& name) {
  return std::any_of(buses.begin(), buses.end(), [&](const ParsedBus& bus) {
    return bus.where.valid("name") && bus.config.name == name;
  });
}

// Resolves `bus` into its sensors; reports unknown names. False when the list is unusable.
bool resolve_sensors(ParsedAggregate& aggregate, const std::vector<ParsedSensor>& sensors,
                     const std::vector<ParsedBus>& buses, ErrorList& errors) {
  AggregateConfig& config = aggregate.config;
  if (!config.bus.empty()) {
    if (!bus_exists(buses, config.bus)) {
      aggregate.where.report(errors, "bus", fmt::format("unknown bus \"{}\"", config.bus));
      return false;
    }
    for (const ParsedSensor& sensor : sensors)
      if (sensor.where.valid("name") && sensor.config.bus == config.bus)
        config.sensors.push_back(sensor.config.name);
    if (config.sensors.empty()) {
      aggregate.where.report(errors, "bus",
                             fmt::format("bus \"{}\" has no [[sensor]] to serve", config.bus));
      return false;
    }
    return true;
  }
  std::vector<std::string> unknown;
  for (const std::string& name : config.sensors)
    if (find_sensor(sensors, name) == nullptr) unknown.push_back(fmt::format("\"{}\"", name));
  if (!unknown.empty())
    aggregate.where.report(errors, "sensors",
                           fmt::format("unknown sensor{} {}", unknown.size() == 1 ? "" : "s",
                                       fmt::join(unknown, ", ")));
  return unknown.empty() && !config.sensors.empty();
}

// The listener of all its sensors; none (reported) when they are served on different ones.
std::optional<std::uint16_t> shared_listener(const ParsedAggregate& aggregate,
                                             const std::vector<ParsedSensor>& sensors,
                                             const std::vector<ParsedBus>& buses,
                                             ErrorList& errors) {
  const std::vector<std::string>& names = aggregate.config.sensors;
  const std::uint16_t first = listener_of_bus(buses, find_sensor(sensors, names.front())->config.bus);
  for (const std::string& name : names) {
    const std::uint16_t listener = listener_of_bus(buses, find_sensor(sensors, name)->config.bus);
    if (listener == first) continue;
    aggregate.where.report(
        errors, "sensors",
        fmt::format("sensor \"{}\" is served on {} but sensor \"{}\" on {}; an aggregate's "
                    "sensors must share one listener (buses with the same tcp_port, or none)",
                    names.front(), describe_listener(first), name, describe_listener(listener)));
    return std::nullopt;
  }
  return first;
}

void check_unit_id(const ParsedAggregate& aggregate, std::uint16_t listener,
                   std::span<const ParsedAggregate> earlier,
                   std::span<const std::optional<std::uint16_t>> earlier_listeners,
                   const std::vector<ParsedSensor>& sensors, const std::vector<ParsedBus>& buses,
                   ErrorList& errors) {
  if (!aggregate.where.valid("unit_id")) return;
  const std::uint8_t id = aggregate.config.unit_id;
  const std::string where = on_listener(listener);
  for (const ParsedSensor& sensor : sensors) {
    if (!sensor.where.valid("unit_id") || sensor.config.unit_id != id ||
        listener_of_bus(buses, sensor.config.bus) != listener)
      continue;
    return aggregate.where.report(
        errors, "unit_id",
        fmt::format("unit id {} is already used by sensor \"{}\" (line {}){}", id,
                    sensor.config.name, sensor.where.header().line, where));
  }
  for (const ParsedBus& bus : buses) {
    const auto& ids = bus.config.pass_through;
    if (listener_of(bus.config) != listener || std::find(ids.begin(), ids.end(), id) == ids.end())
      continue;
    return aggregate.where.report(
        errors, "unit_id",
        fmt::format("unit id {} is passed through on bus \"{}\" (line {}){}", id,
                    bus.config.name, bus.where.header().line, where));
  }
  for (std::size_t i = 0; i < earlier.size(); ++i) {
    if (!earlier[i].where.valid("unit_id") || earlier[i].config.unit_id != id ||
        earlier_listeners[i] != listener)
      continue;
    return aggregate.where.report(
        errors, "unit_id",
        fmt::format("unit id {} is already used by the aggregate at line {}{}", id,
                    earlier[i].where.header().line, where));
  }
}

void check_aggregate_points(const ParsedAggregate& aggregate, const std::vector<ParsedSensor>& sensors,
                  ErrorList& errors, FamilyList families) {
  if (aggregate.config.points.empty()) return;
  std::vector<RegisterMap> maps;
  std::vector<AggregateMember> members;
  maps.reserve(aggregate.config.sensors.size());
  for (const std::string& name : aggregate.config.sensors) {
    const ParsedSensor* sensor = find_sensor(sensors, name);
    if (!sensor->where.valid("model")) return;  // reported with the sensor
    maps.push_back(build_map(families, sensor->config.map, sensor->config.model,
                             sensor->config.family_options.device_values()));
    members.push_back({sensor->config.name, &maps.back()});
  }
  auto layout = make_aggregate_layout(aggregate.config.points, members);
  if (!layout) aggregate.where.report(errors, "points", layout.error());
}

}  // namespace

void check_aggregates(std::vector<ParsedAggregate>& aggregates,
                      const std::vector<ParsedSensor>& sensors,
                      const std::vector<ParsedBus>& buses, bool points, ErrorList& errors,
                      FamilyList families) {
  std::vector<std::optional<std::uint16_t>> listeners;
  for (std::size_t i = 0; i < aggregates.size(); ++i) {
    ParsedAggregate& aggregate = aggregates[i];
    std::optional<std::uint16_t> listener;
    if (resolve_sensors(aggregate, sensors, buses, errors)) {
      listener = shared_listener(aggregate, sensors, buses, errors);
      if (listener)
        check_unit_id(aggregate, *listener, std::span(aggregates).first(i), listeners, sensors,
                      buses, errors);
      if (points) check_aggregate_points(aggregate, sensors, errors, families);
    }
    listeners.push_back(listener);
  }
}

}  // namespace tiltgate::config
