#include "status/status_metrics.h"

#include <fmt/format.h>

#include <cmath>

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

}  // namespace

std::string metrics_text(const GatewayStatus& status) {
  Exposition out;
  out.family("tiltgate_angle_degrees", "gauge",
             "Latest angle per axis in degrees, after mounting, as the register map serves it");
  for (const SensorStatus& s : status.sensors) {
    if (s.x) out.sample(sensor_labels(s) + ",axis=\"x\"", *s.x);
    if (s.y) out.sample(sensor_labels(s) + ",axis=\"y\"", *s.y);
  }
  out.family("tiltgate_tilt_degrees", "gauge", "Latest tilt from vertical in degrees");
  for (const SensorStatus& s : status.sensors)
    if (s.tilt) out.sample(sensor_labels(s), *s.tilt);
  out.family("tiltgate_sensor_online", "gauge",
             "1 when the last exchange with the sensor got a valid reply, else 0");
  for (const SensorStatus& s : status.sensors) out.sample(sensor_labels(s), s.online ? 1 : 0);
  out.family("tiltgate_sensor_stale", "gauge",
             "1 when the sensor has no reading newer than its stale_ms, else 0");
  for (const SensorStatus& s : status.sensors) out.sample(sensor_labels(s), s.stale ? 1 : 0);
  out.family("tiltgate_reading_age_seconds", "gauge",
             "Seconds since the sensor's latest reading arrived");
  for (const SensorStatus& s : status.sensors)
    if (s.age_ms) out.sample(sensor_labels(s), double(*s.age_ms) / 1000.0);
  out.family("tiltgate_alarm_flags", "gauge", "The sensor's alarm bits as the status register shows them");
  for (const SensorStatus& s : status.sensors) out.sample(sensor_labels(s), s.alarms);
  out.family("tiltgate_polls_total", "counter",
             "Measurement polls of the sensor, by result: ok brought a reading, failed did not");
  for (const SensorStatus& s : status.sensors) {
    out.sample(sensor_labels(s) + ",result=\"ok\"", double(s.polls_ok));
    out.sample(sensor_labels(s) + ",result=\"failed\"", double(s.polls_failed));
  }
  out.family("tiltgate_sensor_failures_total", "counter",
             "Failed exchanges with the sensor by reason: timeout (no valid reply in time), "
             "checksum (a reply dropped for its CRC or LRC), io_error (the port failed)");
  for (const SensorStatus& s : status.sensors) {
    out.sample(sensor_labels(s) + ",reason=\"timeout\"", double(s.timeouts));
    out.sample(sensor_labels(s) + ",reason=\"checksum\"", double(s.checksum_errors));
    out.sample(sensor_labels(s) + ",reason=\"io_error\"", double(s.io_errors));
  }
  out.family("tiltgate_sensor_late_replies_total", "counter",
             "Replies that arrived after the reply time-out and were discarded");
  for (const SensorStatus& s : status.sensors) out.sample(sensor_labels(s), double(s.late_replies));
  out.family("tiltgate_sensor_naks_total", "counter",
             "Requests the sensor refused, by the refusal code of its protocol");
  for (const SensorStatus& s : status.sensors)
    for (const auto& [code, count] : s.refusals)
      out.sample(sensor_labels(s) + fmt::format(",code=\"{}\"", code), double(count));
  out.family("tiltgate_bus_polls_total", "counter", "Sensor polls run on the bus");
  for (const BusStatus& b : status.buses) out.sample(bus_labels(b), double(b.polls));
  out.family("tiltgate_bus_writes_total", "counter", "Setting writes carried out on the bus");
  for (const BusStatus& b : status.buses) out.sample(bus_labels(b), double(b.writes));
  out.family("tiltgate_bus_forwarded_total", "counter",
             "Modbus requests passed through to a device on the bus and answered by it");
  for (const BusStatus& b : status.buses) out.sample(bus_labels(b), double(b.forwarded));
  out.family("tiltgate_bus_busy_seconds_total", "counter",
             "Seconds the bus spent in transactions, waiting for replies and time-outs "
             "included; its rate is the share of the wire's time the bus uses");
  for (const BusStatus& b : status.buses) out.sample(bus_labels(b), b.busy_seconds);
  out.family("tiltgate_bus_utilisation_ratio", "gauge",
             "Share of the last seconds the bus was busy, 0 to 1 (1: it cannot poll faster)");
  for (const BusStatus& b : status.buses)
    if (b.utilisation) out.sample(bus_labels(b), *b.utilisation);
  out.single("tiltgate_modbus_clients", "gauge", "Modbus TCP connections open now",
             double(status.modbus_clients));
  out.single("tiltgate_modbus_connections_total", "counter", "Modbus TCP connections accepted",
             double(status.modbus_connections));
  out.single("tiltgate_modbus_connections_refused_total", "counter",
             "Modbus TCP connections closed at once: max_clients or max_clients_per_host "
             "reached and none of those connections idle",
             double(status.modbus_connections_refused));
  out.single("tiltgate_modbus_connections_replaced_total", "counter",
             "Idle Modbus TCP connections closed to make room for a new one",
             double(status.modbus_connections_replaced));
  out.single("tiltgate_modbus_connections_denied_total", "counter",
             "Modbus TCP connections closed at once: the address is not in [server] allow",
             double(status.modbus_connections_denied));
  out.single("tiltgate_modbus_writes_denied_total", "counter",
             "Modbus TCP writes answered 0x01: the address is not in [server] write_allow",
             double(status.modbus_writes_denied));
  out.single("tiltgate_modbus_tls_refused_total", "counter",
             "Modbus/TCP Security connections closed in the TLS handshake: no client "
             "certificate, one not signed by the configured CA, or an older TLS",
             double(status.modbus_tls_refused));
  out.single("tiltgate_http_connections_denied_total", "counter",
             "HTTP connections closed at once: the address is not in [http] allow",
             double(status.http_connections_denied));
  out.family("tiltgate_modbus_requests_total", "counter",
             "Modbus TCP requests answered, by function code (two hex digits)");
  for (const ModbusFunctionCount& f : status.modbus_requests)
    out.sample(fmt::format("function=\"{:02X}\"", f.function), double(f.count));
  out.family("tiltgate_modbus_exceptions_total", "counter",
             "Modbus TCP requests answered with an exception, by function and exception code");
  for (const ModbusExceptionCount& e : status.modbus_exceptions)
    out.sample(fmt::format("function=\"{:02X}\",code=\"{:02X}\"", e.function, e.exception),
               double(e.count));
  if (status.mqtt) {
    const MqttStats& mqtt = *status.mqtt;
    out.single("tiltgate_mqtt_connected", "gauge", "1 while connected to the MQTT broker, else 0",
               mqtt.connected ? 1 : 0);
    out.single("tiltgate_mqtt_published_total", "counter",
               "MQTT messages handed to the broker connection",
               double(mqtt.published));
    out.single("tiltgate_mqtt_dropped_total", "counter",
               "MQTT messages dropped from a full backlog while the broker was away",
               double(mqtt.dropped));
    out.single("tiltgate_mqtt_backlog_messages", "gauge", "MQTT messages waiting for the broker",
               double(mqtt.backlog));
    out.single("tiltgate_mqtt_reconnects_total", "counter",
               "Connections to the MQTT broker after the first",
               double(mqtt.reconnects));
  }
  out.single("tiltgate_process_start_time_seconds", "gauge",
             "Start time of the gateway since the Unix epoch in seconds",
             status.process_start_seconds);
  return out.take();
}

}  // namespace tiltgate
