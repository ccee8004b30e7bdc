// The table RequestRouter answers Modbus requests from (gateway/request_router.h): which
// sensor, aggregate or passed-through bus each unit id goes to, and the options in force.
// Replaced whole, never edited while served, so a request sees one table throughout; a
// connection's reader keeps one until the router's generation says a new one is out.
#pragma once

#include <array>
#include <chrono>
#include <memory>

#include "config/config.h"
#include "gateway/gateway_aggregate.h"
#include "line_scheduling/gateway_sensor.h"

namespace tiltgate {

class BusScheduler;

struct RouterOptions {
  bool writes = false;
  WordOrder word_order = WordOrder::big;
  std::chrono::milliseconds write_timeout{3000};
};

struct UnitRoutes {
  RouterOptions options;
  std::array<std::shared_ptr<GatewaySensor>, 256> units{};
  std::array<std::shared_ptr<GatewayAggregate>, 256> aggregates{};
  // Held: a request forwarded under this table keeps its bus until it is answered.
  std::array<std::shared_ptr<BusScheduler>, 256> forwarded{};
};

}  // namespace tiltgate
