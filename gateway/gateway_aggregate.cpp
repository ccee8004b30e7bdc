#include "gateway/gateway_aggregate.h"

#include <fmt/format.h>

#include <algorithm>

#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

Expected<std::shared_ptr<GatewayAggregate>, std::string> make_gateway_aggregate(
    const AggregateConfig& config, const std::vector<std::shared_ptr<GatewaySensor>>& sensors) {
  auto aggregate = std::make_shared<GatewayAggregate>();
  aggregate->config = config;
  std::vector<AggregateMember> members;
  for (const std::string& name : config.sensors) {
    auto found = std::find_if(sensors.begin(), sensors.end(),
                              [&](const auto& sensor) { return sensor->config.name == name; });
    if (found == sensors.end()) return Unexpected{fmt::format("no sensor \"{}\"", name)};
    aggregate->members.push_back(*found);
    members.push_back({(*found)->config.name, &(*found)->map});
  }
  auto layout = make_aggregate_layout(config.points, members);
  if (!layout) return Unexpected{layout.error()};
  aggregate->layout = std::move(*layout);
  return aggregate;
}

ModbusResponse read_aggregate_unit(const GatewayAggregate& aggregate, const ModbusRequest& request,
                                   WordOrder order, SteadyClock::time_point now) {
  ModbusResponse response;
  const bool registers =
      request.table == ModbusTable::input || request.table == ModbusTable::holding;
  if (request.is_write || !registers ||
      request.function == modbus_function::encapsulated_interface) {
    response.exception = ModbusException::illegal_function;
    return response;
  }
  const MemberRange range = members_in(aggregate.layout, request.address, request.count);
  // Every sensor's snapshot first, taken at one instant (no poll published between them),
  // then the reply from them without a lock.
  std::vector<std::shared_ptr<const SensorSnapshot>> snapshots;
  snapshots.reserve(range.last - range.first);
  {
    const SnapshotSlot::Instant instant;
    for (std::size_t i = range.first; i < range.last; ++i) {
      snapshots.push_back(aggregate.members[i]->snapshot(instant));
      if (snapshots.back() == nullptr) {  // a sensor routed but not yet taken up by its bus
        response.exception = ModbusException::gateway_target_failed;
        return response;
      }
    }
  }
  std::vector<AggregateSource> sources;
  sources.reserve(snapshots.size());
  for (std::size_t i = range.first; i < range.last; ++i) {
    const GatewaySensor& sensor = *aggregate.members[i];
    sources.push_back({&sensor.map, sensor.view(*snapshots[i - range.first], now, order)});
  }
  auto words = read_aggregate(aggregate.layout, range, sources, request.address, request.count);
  if (!words)
    response.exception = ModbusException(std::uint8_t(words.error()));
  else
    response.registers = std::move(*words);
  return response;
}

}  // namespace tiltgate
