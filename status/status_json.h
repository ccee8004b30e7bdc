// The JSON of the HTTP status API (docs/northbound.md, "HTTP status API and metrics"): /api/sensors,
// /api/sensors/{name} and /api/buses. Pure: text from a GatewayStatus.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gateway/gateway_status.h"

namespace tiltgate {

// `text` as a JSON string, quotes included (RFC 8259 section 7: ", \ and control characters
// escaped; other bytes, UTF-8 included, as they are).
std::string json_string(std::string_view text);
// A number, or null for none, NaN and the infinities (JSON has none of them).
std::string json_number(std::optional<double> value);

std::string sensor_json(const SensorStatus& sensor);
std::string sensors_json(const std::vector<SensorStatus>& sensors);  // an array
std::string buses_json(const std::vector<BusStatus>& buses);         // an array
// The Modbus TCP server's connections and who was kept out: /api/modbus.
std::string modbus_json(const GatewayStatus& status);

}  // namespace tiltgate
