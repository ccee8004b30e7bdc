// A PLC acknowledges a sensor's latched alarms by writing 1 to its `acknowledge_alarms` coil
// (coil 0 of the built-in maps; docs/monitoring.md, "Alarms"). The gateway does it itself:
// nothing goes to the sensor, so it is done on the buses' thread, where the sensor's
// processing lives, at once, and recorded in the bus's audit trail like any other change.
#pragma once

#include "line_scheduling/gateway_sensor.h"
#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

// Functions 05 and 0F on a sensor's unit: every coil written must be an acknowledge_alarms
// point (else 0x02, or 0x01 on a map without coils); a 1 among them acknowledges, a 0 alone
// does nothing. Refused (0x04) when the audit trail refuses changes. Buses' thread.
ModbusResponse acknowledge_alarms(GatewaySensor& sensor, const ModbusRequest& request);

}  // namespace tiltgate
