// The JSON of the HTTP status API (docs/northbound.md, "HTTP status API and metrics"): /api/sensors,
// /api/sensors/{name} and /api/buses. Pure: text from a GatewayStatus, written through
// status/json_values.h (strings escaped as RFC 8259 section 7 says, missing numbers null).
#pragma once

#include <string>
#include <vector>

#include "gateway/gateway_status.h"

namespace tiltgate {

std::string sensor_json(const SensorStatus& sensor);
std::string sensors_json(const std::vector<SensorStatus>& sensors);  // an array
std::string buses_json(const std::vector<BusStatus>& buses);         // an array
// The Modbus TCP server's connections and who was kept out: /api/modbus.
std::string modbus_json(const GatewayStatus& status);

}  // namespace tiltgate
