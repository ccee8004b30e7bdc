#include "commission/configured_units.h"

namespace tiltgate {

namespace {

constexpr unsigned kLastUnitId = 247;  // Modbus's last individual address

}  // namespace

ConfiguredUnits configured_units(const Config& config, std::string_view bus) {
  ConfiguredUnits units;
  for (const SensorConfig& sensor : config.sensors) {
    units.unit_ids.insert(sensor.unit_id);
    if (sensor.bus == bus) units.on_bus.emplace(sensor.address, sensor.name);
  }
  for (const AggregateConfig& aggregate : config.aggregates) units.unit_ids.insert(aggregate.unit_id);
  for (const BusConfig& each : config.buses)
    units.unit_ids.insert(each.pass_through.begin(), each.pass_through.end());
  return units;
}

std::vector<std::uint8_t> free_unit_ids(const std::set<std::uint8_t>& taken, std::size_t count) {
  std::vector<std::uint8_t> free;
  for (unsigned id = 1; id <= kLastUnitId && free.size() < count; ++id)
    if (!taken.contains(static_cast<std::uint8_t>(id))) free.push_back(static_cast<std::uint8_t>(id));
  return free;
}

}  // namespace tiltgate
