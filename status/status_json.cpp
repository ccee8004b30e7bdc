#include "status/status_json.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "status/history_format.h"

namespace tiltgate {

namespace {

Json json_integer(std::optional<std::int64_t> value) {
  return value ? Json(*value) : Json(nullptr);
}

template <class Item, class Write>
Json json_array(const std::vector<Item>& items, Write write) {
  Json out = Json::array();
  for (const Item& item : items) out.push_back(write(item));
  return out;
}

// {"3":2,"5":1}: refusals by their protocol's code.
Json naks_json(const std::vector<std::pair<std::uint8_t, std::uint64_t>>& refusals) {
  Json out = Json::object();
  for (const auto& [code, count] : refusals) out[std::to_string(code)] = count;
  return out;
}

// {"filter":2,"zero_x":null}: the settings record, null where unknown.
Json settings_json(const std::vector<std::pair<std::string, std::optional<double>>>& settings) {
  Json out = Json::object();
  for (const auto& [name, value] : settings) out[name] = json_number(value);
  return out;
}

// {"polls_failed":1,"timeout":2,...}: failures by cause, keyed as a sensor's "failures".
Json failures_json(const FailureCounts& c) {
  return Json{{"polls_failed", c.polls_failed},
              {"timeout", c.timeouts},
              {"checksum", c.checksum_errors},
              {"io_error", c.io_errors},
              {"late_reply", c.late_replies}};
}

Json failures_json(const std::optional<FailureCounts>& c) {
  return c ? failures_json(*c) : Json(nullptr);
}

// {"requests":..,"replies":..,...}: the exchanges attempt by attempt (docs/diagnostics.md).
Json exchanges_json(const ExchangeCounts& c) {
  return Json{{"requests", c.requests},
              {"replies", c.replies},
              {"garbled", c.garbled},
              {"no_reply", c.no_reply},
              {"exceptions", c.refused},
              {"naks", c.refused - std::min(c.busy, c.refused)},
              {"busy", c.busy},
              {"bytes_out", c.bytes_out},
              {"bytes_in", c.bytes_in},
              {"overruns", c.overruns},
              {"uart_errors", c.uart_errors}};
}

// The identity's keys, then the reading, the counters and the settings.
Json sensor_object(const SensorStatus& s) {
  Json out = sensor_identity_json(s);
  out.update(Json{{"wrong_device", s.wrong_device},
                  {"online", s.online},
                  {"stale", s.stale},
                  {"x", json_number(s.x)},
                  {"y", json_number(s.y)},
                  {"tilt", json_number(s.tilt)},
                  {"age_ms", json_integer(s.age_ms)},
                  {"alarms", s.alarms},
                  {"alarms_danger", s.alarms_danger},
                  {"alarms_latched", s.alarms_latched},
                  {"relative_x", json_number(s.relative_x)},
                  {"relative_y", json_number(s.relative_y)},
                  {"displacement_x_mm", json_number(s.displacement_x_mm)},
                  {"displacement_y_mm", json_number(s.displacement_y_mm)},
                  {"displacement_mm", json_number(s.displacement_mm)},
                  {"temperature", json_number(s.temperature)},
                  {"reading_time", s.reading_unix_ms ? Json(iso8601_utc(*s.reading_unix_ms))
                                                     : Json(nullptr)},
                  {"clock_synchronised", s.clock_synchronised},
                  {"polls_ok", s.polls_ok},
                  {"polls_failed", s.polls_failed},
                  {"polls_per_s", json_number(s.polls_per_s)},
                  {"failures",
                   {{"timeout", s.timeouts},
                    {"checksum", s.checksum_errors},
                    {"io_error", s.io_errors},
                    {"late_reply", s.late_replies}}},
                  {"failures_10min", failures_json(s.recent_failures)},
                  {"exchanges", exchanges_json(s.exchanges)},
                  {"slowest_reply_ms", s.slowest_reply_ms},
                  {"naks", naks_json(s.refusals)},
                  {"line_seconds", json_number(s.line_seconds)},
                  {"line_share", json_number(s.line_share)},
                  {"settings", settings_json(s.settings)}});
  return out;
}

Json bus_object(const BusStatus& b) {
  return Json{{"name", b.name},
              {"port", b.port},
              {"baud", b.baud},
              {"protocol", b.protocol},
              {"polls", b.polls},
              {"writes", b.writes},
              {"forwarded", b.forwarded},
              {"machine_held", b.machine_held},
              {"overloaded", b.overloaded},
              {"busy_seconds", json_number(b.busy_seconds)},
              {"polls_per_s", json_number(b.polls_per_s)},
              {"utilisation", json_number(b.utilisation)},
              {"restarts", b.restarts},
              {"failures", failures_json(b.failures)},
              {"failures_10min", failures_json(b.recent_failures)},
              {"exchanges", exchanges_json(b.exchanges)},
              {"bytes_out", b.bytes_out},
              {"bytes_in", b.bytes_in},
              {"stray_bytes", b.stray_bytes},
              {"reopens", b.reopens},
              {"black_box", Json{{"keep_s", b.black_box_s},
                                 {"frames", b.black_box_frames},
                                 {"bytes", b.black_box_bytes},
                                 {"dropped", b.black_box_dropped}}},
              {"hint", b.hint ? Json(*b.hint) : Json(nullptr)}};
}

// The warm standby pair of [redundancy] as this gateway sees it (gateway/gateway_status.h
// RedundancyStatus); null without the section.
Json redundancy_object(const std::optional<RedundancyStatus>& r) {
  if (!r) return nullptr;
  return Json{{"configured_role", r->configured_role},
              {"active", r->active},
              {"takeovers", r->takeovers},
              {"step_downs", r->step_downs},
              {"since", json_number(r->since_seconds)},
              {"reason", r->reason},
              {"peer", r->peer},
              {"takeover_ms", r->takeover_ms},
              {"failback", r->failback},
              {"last_request_heard_ms", json_integer(r->last_request_heard_ms)}};
}

// The system clock the readings are stamped with (clock/clock_state.h): synchronised, and
// its error bound in ms while it is (null while not).
Json clock_object(const ClockState& c) {
  return Json{{"synchronised", c.synchronised}, {"error_ms", json_number(c.error_ms)}};
}

}  // namespace

std::string sensor_json(const SensorStatus& sensor) { return json_text(sensor_object(sensor)); }

std::string sensors_json(const std::vector<SensorStatus>& sensors) {
  return json_text(json_array(sensors, sensor_object));
}

std::string modbus_json(const GatewayStatus& s) {
  return json_text(Json{{"clients", s.modbus_clients},
                        {"connections", s.modbus_connections},
                        {"refused", s.modbus_connections_refused},
                        {"replaced", s.modbus_connections_replaced},
                        {"denied", s.modbus_connections_denied},
                        {"writes_denied", s.modbus_writes_denied},
                        {"tls_refused", s.modbus_tls_refused},
                        {"max_requests_per_s", s.modbus_max_requests_per_s},
                        {"max_client_requests_per_s", s.modbus_max_client_requests_per_s},
                        {"requests_delayed", s.modbus_requests_delayed},
                        {"request_delay_seconds", s.modbus_request_delay_seconds},
                        {"http_denied", s.http_connections_denied}});
}

std::string gateway_state_json(const GatewayStatus& s, double now_seconds) {
  // A gateway without [redundancy] is alone on its lines: active.
  const bool standby = s.redundancy && !s.redundancy->active;
  const double uptime = std::floor(std::max(0.0, now_seconds - s.process_start_seconds));
  return json_text(Json{{"role", standby ? "standby" : "active"},
                        {"redundancy", redundancy_object(s.redundancy)},
                        {"uptime_s", json_number(uptime)},
                        {"loaded_at", s.loaded_at.empty() ? Json(nullptr) : Json(s.loaded_at)},
                        {"version", TILTGATE_VERSION},
                        {"clock", clock_object(s.clock)}});
}

std::string buses_json(const std::vector<BusStatus>& buses) {
  return json_text(json_array(buses, bus_object));
}

}  // namespace tiltgate
