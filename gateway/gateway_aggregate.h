// An aggregate unit ([[aggregate]]) as the gateway serves it: the same points of many sensors
// back to back (mapping/aggregate_layout.h), read from their caches.
#pragma once

#include <memory>
#include <vector>

#include "config/config.h"
#include "line_scheduling/gateway_sensor.h"
#include "modbus_tcp/modbus_types.h"
#include "mapping/aggregate_layout.h"

namespace tiltgate {

struct GatewayAggregate {
  AggregateConfig config;
  AggregateLayout layout;
  // In block order. Held: a reload that drops a sensor rebuilds the aggregate, and a request
  // being answered keeps the ones it started with.
  std::vector<std::shared_ptr<GatewaySensor>> members;
};

// The aggregate of `config` over `sensors` (looked up by name); an error when a sensor is
// missing or the layout does not hold (the loader checks both).
Expected<std::shared_ptr<GatewayAggregate>, std::string> make_gateway_aggregate(
    const AggregateConfig& config, const std::vector<std::shared_ptr<GatewaySensor>>& sensors);

// Answers a request for an aggregate unit. FC3 and FC4 read the same registers; every value of
// the reply comes from the sensors' caches at one instant `now`, in one pass that never
// suspends, so no poll lands between two sensors of one reply. Writes and bit reads: 0x01
// (illegal function); so is Read Device Identification (an aggregate is no device).
ModbusResponse read_aggregate_unit(const GatewayAggregate& aggregate, const ModbusRequest& request,
                                   WordOrder order, SteadyClock::time_point now);

// What one reader keeps between aggregate reads, so that a read allocates nothing once these
// have grown: the members' snapshots and views of the read in hand.
struct AggregateScratch {
  std::vector<std::shared_ptr<const SensorSnapshot>> snapshots;
  std::vector<AggregateSource> sources;
};
// The same into `response`, whose vectors keep their capacity.
void read_aggregate_unit(const GatewayAggregate& aggregate, const ModbusRequest& request,
                         WordOrder order, SteadyClock::time_point now, ModbusResponse& response,
                         AggregateScratch& scratch);

}  // namespace tiltgate
