// A Modbus read of one sensor's registers or bits, answered from one snapshot through its
// register map: what RequestRouter::handle() and a connection's reader (gateway/router_reader.h)
// both do. Pure; it fills a response the caller owns, so a connection that
// reuses one allocates nothing.
#pragma once

#include "line_scheduling/gateway_sensor.h"
#include "line_scheduling/sensor_snapshot.h"
#include "mapping/map_access.h"
#include "mapping/register_image.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

RegisterTable table_of(ModbusTable table);
ModbusException exception_for(MapFault fault);

// Replaces `response` with the answer to `request` (a read: 01 to 04) from `snapshot` as it
// reads at `now`: the values, or the map's exception. Its vectors keep their capacity. `image`, when given, is the
// caller's rendering of this snapshot's registers (mapping/register_image.h), which a register
// read copies from.
void read_sensor(const GatewaySensor& sensor, const SensorSnapshot& snapshot,
                 const ModbusRequest& request, WordOrder order, SteadyClock::time_point now,
                 ModbusResponse& response, RegisterImage* image = nullptr);

}  // namespace tiltgate
