#include "status/status_metrics.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <vector>

namespace tiltgate {

std::string metrics_label_value(std::string_view value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string metrics_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", value);
}

namespace {

// Builds one metric family at a time: its HELP and TYPE lines, then its samples.
class Exposition {
 public:
  void family(std::string_view name, std::string_view type, std::string_view help) {
    text_ += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
    name_ = name;
  }
  // A family of one unlabelled sample.
  void single(std::string_view name, std::string_view type, std::string_view help, double value) {
    family(name, type, help);
    sample("", value);
  }
  // `labels` as written between the braces, already escaped; empty for none.
  void sample(const std::string& labels, double value) {
    text_ += name_;
    if (!labels.empty()) text_ += "{" + labels + "}";
    text_ += " " + metrics_value(value) + "\n";
  }
  // One sample of a histogram's series: the family's name with `suffix` (_bucket, _sum, _count).
  void sample(std::string_view suffix, const std::string& labels, double value) {
    text_ += name_;
    text_ += suffix;
    if (!labels.empty()) text_ += "{" + labels + "}";
    text_ += " " + metrics_value(value) + "\n";
  }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
  std::string_view name_;
};

std::string sensor_labels(const SensorStatus& s) {
  return fmt::format("sensor=\"{}\",bus=\"{}\",unit=\"{}\"", metrics_label_value(s.name),
                     metrics_label_value(s.bus), s.unit_id);
}

std::string bus_labels(const BusStatus& b) {
  return fmt::format("bus=\"{}\"", metrics_label_value(b.name));
}

// A family with one sample per sensor (or per bus): none for a value it does not have now.
struct SensorFamily {
  const char* name;
  const char* type;
  const char* help;
  std::optional<double> (*value)(const SensorStatus&);
};

const SensorFamily kSensorFamilies[] = {
    // The exchanges attempt by attempt (docs/diagnostics.md), as FC 08 counts them.
    {"tiltgate_sensor_requests_total", "counter",
     "Requests written to the sensor, retries included",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.requests); }},
    {"tiltgate_sensor_replies_total", "counter",
     "Valid replies taken from the sensor, refusals included",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.replies); }},
    {"tiltgate_sensor_garbled_replies_total", "counter",
     "Attempts answered with bytes that made no valid reply: a broken checksum, a wrong "
     "length, a collision",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.garbled); }},
    {"tiltgate_sensor_no_reply_total", "counter",
     "Attempts that heard nothing at all from the sensor in time",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.no_reply); }},
    {"tiltgate_sensor_busy_total", "counter",
     "Refusals that said the sensor was busy (its protocol's busy code)",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.busy); }},
    {"tiltgate_sensor_overruns_total", "counter",
     "Characters the gateway's port lost to a UART overrun during the sensor's replies (0 "
     "where the port cannot count them)",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.overruns); }},
    {"tiltgate_sensor_uart_errors_total", "counter",
     "Characters of the sensor's replies the gateway's UART got with a framing or parity error: "
     "a wrong rate or parity, noise (0 where the port cannot count them)",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.exchanges.uart_errors); }},
    {"tiltgate_tilt_degrees", "gauge", "Latest tilt from vertical in degrees",
     [](const SensorStatus& s) { return s.tilt; }},
    {"tiltgate_sensor_online", "gauge",
     "1 when the last exchange with the sensor got a valid reply, else 0",
     [](const SensorStatus& s) -> std::optional<double> { return s.online ? 1 : 0; }},
    {"tiltgate_sensor_stale", "gauge",
     "1 when the sensor has no reading newer than its stale_ms, else 0",
     [](const SensorStatus& s) -> std::optional<double> { return s.stale ? 1 : 0; }},
    {"tiltgate_sensor_wrong_device", "gauge",
     "1 while another device than the sensor's configured serial answers at its address (its "
     "measurements read as offline), else 0",
     [](const SensorStatus& s) -> std::optional<double> { return s.wrong_device ? 1 : 0; }},
    {"tiltgate_sensor_wrong_device_total", "counter",
     "Times another device than the sensor's configured serial was found answering at its address",
     [](const SensorStatus& s) -> std::optional<double> { return double(s.wrong_device_found); }},
    {"tiltgate_reading_age_seconds", "gauge", "Seconds since the sensor's latest reading arrived",
     [](const SensorStatus& s) -> std::optional<double> {
       if (!s.age_ms) return std::nullopt;
       return double(*s.age_ms) / 1000.0;
     }},
    {"tiltgate_alarm_flags", "gauge", "The sensor's alarm bits as the status register shows them",
     [](const SensorStatus& s) -> std::optional<double> { return s.alarms; }},
    {"tiltgate_sensor_line_seconds_total", "counter",
     "Seconds its bus's line spent on the sensor's polls, writes and retries, waiting for "
     "replies, time-outs and late-reply guards included",
     [](const SensorStatus& s) -> std::optional<double> { return s.line_seconds; }},
    {"tiltgate_sensor_line_share_ratio", "gauge",
     "The sensor's share of its bus's line over the last seconds, 0 to 1: who eats the line",
     [](const SensorStatus& s) { return s.line_share; }},
};

struct BusFamily {
  const char* name;
  const char* type;
  const char* help;
  std::optional<double> (*value)(const BusStatus&);
};

const BusFamily kBusFamilies[] = {
    {"tiltgate_bus_stray_bytes_total", "counter",
     "Bytes found waiting on the line before a request and dropped unread: noise, a babbling "
     "device, a reply later than its late-reply window",
     [](const BusStatus& b) -> std::optional<double> { return double(b.stray_bytes); }},
    {"tiltgate_bus_black_box_bytes", "gauge",
     "Memory the bus's black box holds: its frames of the last black_box_s seconds and their "
     "bookkeeping",
     [](const BusStatus& b) -> std::optional<double> { return double(b.black_box_bytes); }},
    {"tiltgate_bus_black_box_dropped_total", "counter",
     "Frames the bus's black box let go before their time, to stay within its memory bound",
     [](const BusStatus& b) -> std::optional<double> { return double(b.black_box_dropped); }},
    {"tiltgate_bus_polls_total", "counter", "Sensor polls run on the bus",
     [](const BusStatus& b) -> std::optional<double> { return double(b.polls); }},
    {"tiltgate_bus_writes_total", "counter", "Setting writes carried out on the bus",
     [](const BusStatus& b) -> std::optional<double> { return double(b.writes); }},
    {"tiltgate_bus_forwarded_total", "counter",
     "Modbus requests passed through to a device on the bus and answered by it",
     [](const BusStatus& b) -> std::optional<double> { return double(b.forwarded); }},
    {"tiltgate_bus_busy_seconds_total", "counter",
     "Seconds the bus spent in transactions, waiting for replies and time-outs included; its "
     "rate is the share of the wire's time the bus uses",
     [](const BusStatus& b) -> std::optional<double> { return b.busy_seconds; }},
    {"tiltgate_bus_restarts_total", "counter",
     "Times the bus's loop or a sensor's poller failed (an exception, logged at error) and went "
     "on after a pause; 0 in a healthy gateway",
     [](const BusStatus& b) -> std::optional<double> { return double(b.restarts); }},
    {"tiltgate_bus_machine_held_total", "counter",
     "Reply waits made longer because this machine had not handed on what the line received by "
     "their deadline (the kernel's tty worker waited for a core): the machine's lateness, no "
     "device's",
     [](const BusStatus& b) -> std::optional<double> { return double(b.machine_held); }},
    {"tiltgate_bus_overloaded_total", "counter",
     "Attempts given up because this machine held the line's bytes more than 2 s past the reply "
     "deadline: nothing learnt of the device, which is not blamed",
     [](const BusStatus& b) -> std::optional<double> { return double(b.overloaded); }},
    {"tiltgate_bus_utilisation_ratio", "gauge",
     "Share of the last seconds the bus was busy, 0 to 1 (1: it cannot poll faster)",
     [](const BusStatus& b) { return b.utilisation; }},
};

// A family of one unlabelled sample from the gateway as a whole.
struct GatewaySingle {
  const char* name;
  const char* type;
  const char* help;
  double (*value)(const GatewayStatus&);
};

const GatewaySingle kModbusSingles[] = {
    {"tiltgate_modbus_clients", "gauge", "Modbus TCP connections open now",
     [](const GatewayStatus& g) { return double(g.modbus_clients); }},
    {"tiltgate_modbus_connections_total", "counter", "Modbus TCP connections accepted",
     [](const GatewayStatus& g) { return double(g.modbus_connections); }},
    {"tiltgate_modbus_connections_refused_total", "counter",
     "Modbus TCP connections closed at once: max_clients or max_clients_per_host reached and "
     "none of those connections idle",
     [](const GatewayStatus& g) { return double(g.modbus_connections_refused); }},
    {"tiltgate_modbus_connections_replaced_total", "counter",
     "Idle Modbus TCP connections closed to make room for a new one",
     [](const GatewayStatus& g) { return double(g.modbus_connections_replaced); }},
    {"tiltgate_modbus_connections_denied_total", "counter",
     "Modbus TCP connections closed at once: the address is not in [server] allow",
     [](const GatewayStatus& g) { return double(g.modbus_connections_denied); }},
    {"tiltgate_modbus_writes_denied_total", "counter",
     "Modbus TCP writes answered 0x01: the address is not in [server] write_allow, or a TLS "
     "client's certificate role may only read",
     [](const GatewayStatus& g) { return double(g.modbus_writes_denied); }},
    {"tiltgate_modbus_tls_refused_total", "counter",
     "Modbus/TCP Security connections closed in the TLS handshake: no client certificate, one "
     "not signed by the configured CA, or an older TLS",
     [](const GatewayStatus& g) { return double(g.modbus_tls_refused); }},
    {"tiltgate_modbus_max_requests_per_second", "gauge",
     "[server] max_requests_per_s in force: Modbus TCP requests answered a second from every "
     "client together, beyond which a request waits for its turn (0: no limit)",
     [](const GatewayStatus& g) { return double(g.modbus_max_requests_per_s); }},
    {"tiltgate_modbus_max_client_requests_per_second", "gauge",
     "[server] max_client_requests_per_s in force: the same for each connection (0: no limit)",
     [](const GatewayStatus& g) { return double(g.modbus_max_client_requests_per_s); }},
    {"tiltgate_modbus_requests_delayed_total", "counter",
     "Modbus TCP requests that waited for their turn under the request rates (answered later, "
     "never refused)",
     [](const GatewayStatus& g) { return double(g.modbus_requests_delayed); }},
    {"tiltgate_modbus_request_delay_seconds_total", "counter",
     "The time those requests waited for their turn, together",
     [](const GatewayStatus& g) { return g.modbus_request_delay_seconds; }},
    {"tiltgate_http_connections_denied_total", "counter",
     "HTTP connections closed at once: the address is not in [http] allow",
     [](const GatewayStatus& g) { return double(g.http_connections_denied); }},
    {"tiltgate_http_max_requests_per_second", "gauge",
     "[http] max_requests_per_s in force: HTTP requests answered a second from every client "
     "together, beyond which a request waits for its turn (0: no limit)",
     [](const GatewayStatus& g) { return double(g.http_rates.max_requests_per_s); }},
    {"tiltgate_http_max_client_requests_per_second", "gauge",
     "[http] max_client_requests_per_s in force: the same for each connection (0: no limit)",
     [](const GatewayStatus& g) { return double(g.http_rates.max_client_requests_per_s); }},
    {"tiltgate_http_requests_delayed_total", "counter",
     "HTTP requests that waited for their turn under the request rates (answered later)",
     [](const GatewayStatus& g) { return double(g.http_rates.requests_delayed); }},
    {"tiltgate_http_request_delay_seconds_total", "counter",
     "The time those requests waited for their turn, together",
     [](const GatewayStatus& g) { return g.http_rates.delay_seconds; }},
    {"tiltgate_http_logins_total", "counter", "Web console logins that succeeded",
     [](const GatewayStatus& g) { return double(g.console.logins); }},
    {"tiltgate_http_login_failures_total", "counter",
     "Web console logins refused: a wrong user name or password",
     [](const GatewayStatus& g) { return double(g.console.login_failures); }},
    {"tiltgate_http_logins_throttled_total", "counter",
     "Web console logins refused with 429 before any password check: too many failures lately "
     "from the address or for the account",
     [](const GatewayStatus& g) { return double(g.console.logins_throttled); }},
    {"tiltgate_http_sessions", "gauge", "Web console sessions open now",
     [](const GatewayStatus& g) { return double(g.console.sessions); }},
};

struct MqttSingle {
  const char* name;
  const char* type;
  const char* help;
  double (*value)(const MqttStats&);
};

const MqttSingle kMqttSingles[] = {
    {"tiltgate_mqtt_connected", "gauge", "1 while connected to the MQTT broker, else 0",
     [](const MqttStats& m) { return m.connected ? 1.0 : 0.0; }},
    {"tiltgate_mqtt_published_total", "counter", "MQTT messages handed to the broker connection",
     [](const MqttStats& m) { return double(m.published); }},
    {"tiltgate_mqtt_dropped_total", "counter",
     "MQTT messages dropped from a full backlog while the broker was away",
     [](const MqttStats& m) { return double(m.dropped); }},
    {"tiltgate_mqtt_backlog_messages", "gauge", "MQTT messages waiting for the broker",
     [](const MqttStats& m) { return double(m.backlog); }},
    {"tiltgate_mqtt_reconnects_total", "counter", "Connections to the MQTT broker after the first",
     [](const MqttStats& m) { return double(m.reconnects); }},
};

struct SparkplugSingle {
  const char* name;
  const char* type;
  const char* help;
  double (*value)(const SparkplugStats&);
};

const SparkplugSingle kSparkplugSingles[] = {
    {"tiltgate_sparkplug_connected", "gauge",
     "1 while the Sparkplug B edge node is connected to its broker, else 0",
     [](const SparkplugStats& s) { return s.connected ? 1.0 : 0.0; }},
    {"tiltgate_sparkplug_published_total", "counter",
     "Sparkplug B messages handed to the broker connection (births, data, deaths, replayed)",
     [](const SparkplugStats& s) { return double(s.published); }},
    {"tiltgate_sparkplug_max_commands_per_second", "gauge",
     "[sparkplug] max_commands_per_s in force: messages from the broker taken a second, beyond "
     "which the next waits for its turn (0: no limit)",
     [](const SparkplugStats& s) { return double(s.max_commands_per_s); }},
    {"tiltgate_sparkplug_commands_delayed_total", "counter",
     "Messages from the broker (NCMD, DCMD, STATE) that waited for their turn under "
     "max_commands_per_s",
     [](const SparkplugStats& s) { return double(s.commands_delayed); }},
};

// A warm standby pair's ([redundancy]): which of the two holds the lines, and how often this one
// took them, so an alert can fire on a takeover or on neither gateway being active.
void add_redundancy_families(Exposition& out, const RedundancyStatus& pair) {
  out.single("tiltgate_redundancy_active", "gauge",
             "1 while this gateway is the active one of its redundant pair and polls its lines, "
             "0 while it is the standby and only listens",
             pair.active ? 1.0 : 0.0);
  out.single("tiltgate_redundancy_takeovers_total", "counter",
             "Times this gateway took its lines over from the other of its redundant pair since "
             "start",
             double(pair.takeovers));
}

// The system clock the readings are stamped with (docs/operations.md, "The clock"): whether
// it is synchronised, and its error bound in seconds, base units as every other metric here
// (the status API's error_ms); no sample while there is no bound, as for other values the
// gateway does not have.
void add_clock_families(Exposition& out, const ClockState& clock) {
  out.single("tiltgate_clock_synchronised", "gauge",
             "1 while the system clock is synchronised by a time service (the kernel's maximum "
             "error below 16 s), else 0; readings taken meanwhile are flagged",
             clock.synchronised ? 1.0 : 0.0);
  out.family("tiltgate_clock_error_seconds", "gauge",
             "The bound on the system clock's error in seconds (the kernel's maxerror), while "
             "it is synchronised");
  if (clock.error_ms) out.sample("", *clock.error_ms / 1000.0);
}

void add_sparkplug_families(Exposition& out, const SparkplugStats& stats) {
  for (const SparkplugSingle& single : kSparkplugSingles)
    out.single(single.name, single.type, single.help, single.value(stats));
  out.family("tiltgate_sparkplug_commands_total", "counter",
             "Sparkplug B commands received, by result: rebirth, write (a setting written or "
             "under way), refused (not a writable setting, or refused by the write), ignored "
             "(commands off), malformed");
  out.sample("result=\"rebirth\"", double(stats.rebirth));
  out.sample("result=\"write\"", double(stats.write));
  out.sample("result=\"refused\"", double(stats.refused));
  out.sample("result=\"ignored\"", double(stats.ignored));
  out.sample("result=\"malformed\"", double(stats.malformed));
}

struct StoreFamily {
  const char* name;
  const char* type;
  const char* help;
  double (*value)(const StoreStats&);
};

const StoreFamily kStoreFamilies[] = {
    {"tiltgate_store_bytes", "gauge", "Size of a feed's store-and-forward files on disk in bytes",
     [](const StoreStats& s) { return double(s.bytes); }},
    {"tiltgate_store_records", "gauge", "Messages kept in a feed's store, not yet replayed",
     [](const StoreStats& s) { return double(s.records); }},
    {"tiltgate_store_dropped_total", "counter",
     "Messages dropped from a feed's full store, oldest first, or refused as too large",
     [](const StoreStats& s) { return double(s.dropped); }},
    {"tiltgate_store_replayed_total", "counter",
     "Messages of a feed's store published again once the broker was back",
     [](const StoreStats& s) { return double(s.replayed); }},
    {"tiltgate_store_lost_total", "counter",
     "Messages of a feed's store lost to a damaged file: a corrupt or torn record and the rest "
     "of its segment",
     [](const StoreStats& s) { return double(s.lost); }},
};

void add_store_families(Exposition& out, const std::vector<StoreStats>& stores) {
  if (stores.empty()) return;
  for (const StoreFamily& f : kStoreFamilies) {
    out.family(f.name, f.type, f.help);
    for (const StoreStats& store : stores)
      out.sample(fmt::format("feed=\"{}\"", metrics_label_value(store.feed)), f.value(store));
  }
}

// The sensors' families, the ones with labels of their own (axis, result, reason, code) first.
void add_sensor_families(Exposition& out, const std::vector<SensorStatus>& sensors) {
  out.family("tiltgate_angle_degrees", "gauge",
             "Latest angle per axis in degrees, after mounting, as the register map serves it");
  for (const SensorStatus& s : sensors) {
    if (s.x) out.sample(sensor_labels(s) + ",axis=\"x\"", *s.x);
    if (s.y) out.sample(sensor_labels(s) + ",axis=\"y\"", *s.y);
  }
  for (const SensorFamily& f : kSensorFamilies) {
    out.family(f.name, f.type, f.help);
    for (const SensorStatus& s : sensors)
      if (const auto value = f.value(s)) out.sample(sensor_labels(s), *value);
  }
  out.family("tiltgate_polls_total", "counter",
             "Measurement polls of the sensor, by result: ok brought a reading, failed did not");
  for (const SensorStatus& s : sensors) {
    out.sample(sensor_labels(s) + ",result=\"ok\"", double(s.polls_ok));
    out.sample(sensor_labels(s) + ",result=\"failed\"", double(s.polls_failed));
  }
  out.family("tiltgate_sensor_failures_total", "counter",
             "Failed exchanges with the sensor by reason: timeout (no valid reply in time), "
             "checksum (a reply dropped for its CRC or LRC), io_error (the port failed)");
  for (const SensorStatus& s : sensors) {
    out.sample(sensor_labels(s) + ",reason=\"timeout\"", double(s.timeouts));
    out.sample(sensor_labels(s) + ",reason=\"checksum\"", double(s.checksum_errors));
    out.sample(sensor_labels(s) + ",reason=\"io_error\"", double(s.io_errors));
  }
  out.family("tiltgate_sensor_late_replies_total", "counter",
             "Replies that arrived after the reply time-out and were discarded");
  for (const SensorStatus& s : sensors) out.sample(sensor_labels(s), double(s.late_replies));
  out.family("tiltgate_sensor_slowest_reply_seconds", "gauge",
             "The longest a reply took since start, from the end of its request to its last "
             "byte, as the line waited for it (what this machine held it back included)");
  for (const SensorStatus& s : sensors)
    out.sample(sensor_labels(s), double(s.slowest_reply_ms) / 1000.0);
  out.family("tiltgate_sensor_reply_seconds", "histogram",
             "Reply times, from the end of the request to the reply's last byte as the line "
             "waited for it (what this machine held it back included), whole milliseconds");
  for (const SensorStatus& s : sensors) {
    std::uint64_t below = 0;
    for (std::size_t i = 0; i < kReplyBucketsMs.size(); ++i) {
      below += s.reply_buckets[i];
      out.sample("_bucket", fmt::format("{},le=\"{}\"", sensor_labels(s),
                                        metrics_value(kReplyBucketsMs[i] / 1000.0)),
                 double(below));
    }
    below += s.reply_buckets.back();
    out.sample("_bucket", sensor_labels(s) + ",le=\"+Inf\"", double(below));
    out.sample("_sum", sensor_labels(s), double(s.reply_ms_sum) / 1000.0);
    out.sample("_count", sensor_labels(s), double(below));
  }
  out.family("tiltgate_sensor_bytes_total", "counter",
             "Bytes of the sensor's exchanges, by direction: out written to it, in read from the "
             "line while it was asked (late and garbled replies included)");
  for (const SensorStatus& s : sensors) {
    out.sample(sensor_labels(s) + ",direction=\"out\"", double(s.exchanges.bytes_out));
    out.sample(sensor_labels(s) + ",direction=\"in\"", double(s.exchanges.bytes_in));
  }
  out.family("tiltgate_sensor_naks_total", "counter",
             "Requests the sensor refused, by the refusal code of its protocol");
  for (const SensorStatus& s : sensors)
    for (const auto& [code, count] : s.refusals)
      out.sample(sensor_labels(s) + fmt::format(",code=\"{}\"", code), double(count));
}

}  // namespace

std::string metrics_text(const GatewayStatus& status) {
  Exposition out;
  add_sensor_families(out, status.sensors);
  for (const BusFamily& f : kBusFamilies) {
    out.family(f.name, f.type, f.help);
    for (const BusStatus& b : status.buses)
      if (const auto value = f.value(b)) out.sample(bus_labels(b), *value);
  }
  out.family("tiltgate_bus_bytes_total", "counter",
             "Bytes the bus's line carried, by direction: out written, in read (polls, writes, "
             "commands and forwarded requests alike, stray bytes included)");
  for (const BusStatus& b : status.buses) {
    out.sample(bus_labels(b) + ",direction=\"out\"", double(b.bytes_out));
    out.sample(bus_labels(b) + ",direction=\"in\"", double(b.bytes_in));
  }
  for (const GatewaySingle& single : kModbusSingles)
    out.single(single.name, single.type, single.help, single.value(status));
  out.family("tiltgate_http_clients_closed_total", "counter",
             "HTTP connections closed for cause since [http] last started, by reason: refused "
             "(max_clients or max_clients_per_host reached, every connection busy answering), "
             "replaced (waiting for a whole request, closed to make room for a new client), "
             "timeout (no whole request within the request time-out), bad_request (malformed "
             "or too large)");
  const HttpClientsClosed& closed = status.http_clients_closed;
  out.sample("reason=\"refused\"", double(closed.refused));
  out.sample("reason=\"replaced\"", double(closed.replaced));
  out.sample("reason=\"timeout\"", double(closed.timed_out));
  out.sample("reason=\"bad_request\"", double(closed.bad_request));
  out.family("tiltgate_modbus_requests_total", "counter",
             "Modbus TCP requests answered, by function code (two hex digits)");
  for (const ModbusFunctionCount& f : status.modbus_requests)
    out.sample(fmt::format("function=\"{:02X}\"", f.function), double(f.count));
  out.family("tiltgate_modbus_exceptions_total", "counter",
             "Modbus TCP requests answered with an exception, by function and exception code");
  for (const ModbusExceptionCount& e : status.modbus_exceptions)
    out.sample(fmt::format("function=\"{:02X}\",code=\"{:02X}\"", e.function, e.exception),
               double(e.count));
  if (status.mqtt)
    for (const MqttSingle& single : kMqttSingles)
      out.single(single.name, single.type, single.help, single.value(*status.mqtt));
  if (status.sparkplug) add_sparkplug_families(out, *status.sparkplug);
  if (status.redundancy) add_redundancy_families(out, *status.redundancy);
  add_store_families(out, status.stores);
  out.family("tiltgate_audit_records_total", "counter",
             "Changes recorded in the audit trail since start, by door (modbus, sparkplug, "
             "control socket, console) and result: ack, nak, timeout, refused, error, ok");
  for (const AuditCount& count : status.audit)
    out.sample(fmt::format("door=\"{}\",result=\"{}\"", metrics_label_value(count.door),
                           metrics_label_value(count.result)),
               double(count.records));
  out.single("tiltgate_audit_records_held", "gauge",
             "Audit records the disk refused, held in memory to be written once it takes them",
             double(status.audit_health.held));
  out.single("tiltgate_audit_records_lost_total", "counter",
             "Audit records lost since start: the disk refused them past [audit] memory_kib",
             double(status.audit_health.lost));
  out.single("tiltgate_audit_disk_refuses", "gauge",
             "1 while the disk refuses the audit trail's records",
             status.audit_health.disk_refuses ? 1.0 : 0.0);
  add_clock_families(out, status.clock);
  out.single("tiltgate_process_start_time_seconds", "gauge",
             "Start time of the gateway since the Unix epoch in seconds",
             status.process_start_seconds);
  // Prometheus's process collector's names: a descriptor leak shows here first.
  if (status.process_open_fds)
    out.single("process_open_fds", "gauge", "Number of open file descriptors.",
               *status.process_open_fds);
  if (status.process_max_fds)
    out.single("process_max_fds", "gauge", "Maximum number of open file descriptors.",
               *status.process_max_fds);
  return out.take();
}

}  // namespace tiltgate
