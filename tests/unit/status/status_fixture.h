// A fixed GatewayStatus for the tests of what is built from it (the status API's JSON, the
// /metrics text, the HTTP routes): a sensor with a reading, a silent one, a bus, a plant.
#pragma once

#include <cmath>
#include <string>

#include "gateway/gateway_status.h"

namespace tiltgate::test {

inline SensorStatus boom() {
  SensorStatus s;
  s.name = "boom";
  s.bus = "line1";
  s.unit_id = 3;
  s.address = 223;
  s.model = "m1";
  s.serial = "962285";
  s.firmware = "1.2";
  s.online = true;
  s.stale = false;
  s.x = 1.5;
  s.y = -2.25;
  s.tilt = 2.7;
  s.age_ms = 40;
  s.alarms = 5;
  s.polls_ok = 10;
  s.polls_failed = 2;
  s.polls_per_s = 4.5;
  s.timeouts = 3;
  s.checksum_errors = 1;
  s.late_replies = 4;
  s.exchanges = ExchangeCounts{14, 10, 1, 3, 3, 1, 140, 200, 0, 2};
  s.slowest_reply_ms = 7;
  s.reply_buckets[1] = 8;  // within 2 ms
  s.reply_buckets[3] = 2;  // within 10 ms
  s.reply_ms_sum = 30;
  s.refusals = {{3, 2}, {5, 1}};
  s.line_seconds = 12.5;
  s.line_share = 0.031;
  s.settings = {{"filter", 2.0}, {"zero_x", std::nullopt}};
  return s;
}

// A sensor that has never answered: every value it would have read is missing.
inline SensorStatus silent(std::string name) {
  SensorStatus s;
  s.name = std::move(name);
  s.bus = "line1";
  s.unit_id = 4;
  s.model = "m1";
  return s;
}

inline BusStatus bus(std::string name, std::string port, std::uint32_t baud) {
  BusStatus b;
  b.name = std::move(name);
  b.port = std::move(port);
  b.baud = baud;
  b.protocol = "p1";
  return b;
}

inline GatewayStatus plant() {
  GatewayStatus status;
  status.sensors = {boom(), silent("mast")};
  status.buses = {bus("line1", "/dev/ttyUSB0", 125000)};
  status.buses[0].polls = 12;
  status.buses[0].writes = 1;
  status.buses[0].busy_seconds = 1.25;
  status.buses[0].polls_per_s = 9.5;
  status.buses[0].utilisation = 0.5;
  status.buses[0].machine_held = 3;
  status.buses[0].overloaded = 1;
  status.buses[0].bytes_out = 500;
  status.buses[0].bytes_in = 706;
  status.buses[0].stray_bytes = 6;
  status.buses[0].black_box_s = 60;
  status.buses[0].black_box_frames = 40;
  status.buses[0].black_box_bytes = 9000;
  status.buses[0].black_box_dropped = 2;
  status.modbus_clients = 2;
  status.modbus_connections = 6;
  status.modbus_connections_refused = 1;
  status.modbus_connections_replaced = 3;
  status.modbus_connections_denied = 4;
  status.modbus_writes_denied = 5;
  status.http_connections_denied = 2;
  status.http_clients_closed = {.refused = 7, .replaced = 8, .timed_out = 9, .bad_request = 10};
  status.modbus_tls_refused = 6;
  status.modbus_max_requests_per_s = 20000;
  status.modbus_max_client_requests_per_s = 5000;
  status.modbus_requests_delayed = 11;
  status.http_rates = {.max_requests_per_s = 400, .max_client_requests_per_s = 100,
                       .requests_delayed = 7, .delay_seconds = 0.5};
  status.modbus_request_delay_seconds = 0.25;
  status.modbus_requests = {{0x03, 7}, {0x2B, 1}};
  status.modbus_exceptions = {{0x03, 0x02, 1}};
  status.process_start_seconds = 1700000000.5;
  return status;
}

}  // namespace tiltgate::test
