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
  AggregateScratch scratch;
  read_aggregate_unit(aggregate, request, order, now, response, scratch);
  return response;
}

void read_aggregate_unit(const GatewayAggregate& aggregate, const ModbusRequest& request,
                         WordOrder order, SteadyClock::time_point now, ModbusResponse& response,
                         AggregateScratch& scratch) {
  response.exception.reset();
  response.registers.clear();
  response.bits.clear();
  response.device_objects.clear();
  const bool registers =
      request.table == ModbusTable::input || request.table == ModbusTable::holding;
  if (request.is_write || !registers ||
      request.function == modbus_function::encapsulated_interface) {
    response.exception = ModbusException::illegal_function;
    return;
  }
  const MemberRange range = members_in(aggregate.layout, request.address, request.count);
  // Every sensor's snapshot first, taken at one instant (no poll published between them),
  // then the reply from them without a lock.
  scratch.snapshots.clear();
  scratch.sources.clear();
  {
    const SnapshotSlot::Instant instant;
    for (std::size_t i = range.first; i < range.last; ++i) {
      scratch.snapshots.push_back(aggregate.members[i]->snapshot(instant));
      if (scratch.snapshots.back() == nullptr) {  // a sensor routed but not yet taken up by its bus
        response.exception = ModbusException::gateway_target_failed;
        return;
      }
    }
  }
  for (std::size_t i = range.first; i < range.last; ++i) {
    const GatewaySensor& sensor = *aggregate.members[i];
    scratch.sources.push_back(
        {&sensor.map, sensor.view(*scratch.snapshots[i - range.first], now, order)});
  }
  response.registers.resize(request.count);  // within its capacity after the first reads
  auto read = read_aggregate(aggregate.layout, range, scratch.sources, request.address,
                             response.registers);
  if (!read) {
    response.registers.clear();
    response.exception = ModbusException(std::uint8_t(read.error()));
  }
  // Not kept past the read: a reload may drop these sensors.
  scratch.snapshots.clear();
}

}  // namespace tiltgate
