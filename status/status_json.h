// The JSON of the HTTP status API (docs/northbound.md, "HTTP status API and metrics"): /api/sensors,
// /api/sensors/{name}, /api/buses, /api/modbus and /api/status. Pure: text from a GatewayStatus, written through
// status/json_values.h (strings escaped as RFC 8259 section 7 says, missing numbers null).
#pragma once

#include <string>
#include <vector>

#include "gateway/gateway_status.h"
#include "status/json_values.h"

namespace tiltgate {

// A sensor's identity: name, bus, unit_id, address, model, serial, firmware and
// configured_serial (null unless configured). The first keys of each /api/sensors object, and
// the MQTT feed's info payload. Inline, as the MQTT feed does not link the HTTP server.
inline Json sensor_identity_json(const SensorStatus& s) {
  return Json{{"name", s.name},
              {"bus", s.bus},
              {"unit_id", s.unit_id},
              {"address", s.address},
              {"model", s.model},
              {"serial", s.serial},
              {"firmware", s.firmware},
              {"configured_serial",
               s.configured_serial.empty() ? Json(nullptr) : Json(s.configured_serial)}};
}

std::string sensor_json(const SensorStatus& sensor);
std::string sensors_json(const std::vector<SensorStatus>& sensors);  // an array
std::string buses_json(const std::vector<BusStatus>& buses);         // an array
// The Modbus TCP server's connections and who was kept out: /api/modbus.
std::string modbus_json(const GatewayStatus& status);
// The gateway itself, /api/status: whether it is the active one or the standby of a redundant
// pair, the pair's state, its uptime at `now_seconds` (Unix time), when its configuration was
// loaded, its version and its clock (synchronised, error_ms).
std::string gateway_state_json(const GatewayStatus& status, double now_seconds);

}  // namespace tiltgate
