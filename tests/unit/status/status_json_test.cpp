// The status API's JSON and the /metrics text, built from a fixed GatewayStatus: fields and
// their order, nulls where a value is missing, and escaping of names that need it.
#include <doctest/doctest.h>

#include <cmath>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "http/http_routes.h"
#include "status/json_values.h"
#include "status/status_json.h"
#include "status/status_metrics.h"

using namespace tiltgate;

namespace {

SensorStatus boom() {
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
SensorStatus silent(std::string name) {
  SensorStatus s;
  s.name = std::move(name);
  s.bus = "line1";
  s.unit_id = 4;
  s.model = "m1";
  return s;
}

BusStatus bus(std::string name, std::string port, std::uint32_t baud) {
  BusStatus b;
  b.name = std::move(name);
  b.port = std::move(port);
  b.baud = baud;
  b.protocol = "p1";
  return b;
}

GatewayStatus plant() {
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

}  // namespace

TEST_CASE("status JSON: a sensor with a reading shows every field") {
  CHECK(sensor_json(boom()) ==
        R"({"name":"boom","bus":"line1","unit_id":3,"address":223,"model":"m1",)"
        R"("serial":"962285","firmware":"1.2","configured_serial":null,"wrong_device":false,)"
        R"("online":true,"stale":false,"x":1.5,"y":-2.25,)"
        R"("tilt":2.7,"age_ms":40,"alarms":5,"polls_ok":10,"polls_failed":2,"polls_per_s":4.5,)"
        R"("failures":{"timeout":3,"checksum":1,"io_error":0,"late_reply":4},)"
        R"("failures_10min":null,)"
        R"("slowest_reply_ms":7,"naks":{"3":2,"5":1},"line_seconds":12.5,"line_share":0.031,)"
        R"("settings":{"filter":2,"zero_x":null}})");
}

TEST_CASE("status JSON: a wrong device shows the configured serial beside the one answering") {
  SensorStatus swapped = boom();
  swapped.serial = "9600007";
  swapped.configured_serial = "9600223";
  swapped.wrong_device = true;
  CHECK(sensor_json(swapped).find(R"("serial":"9600007","firmware":"1.2",)"
                                  R"("configured_serial":"9600223","wrong_device":true,)") !=
        std::string::npos);
}

TEST_CASE("status JSON: missing angles and age are null, never NaN") {
  SensorStatus single = boom();
  single.y = std::nullopt;
  CHECK(sensor_json(single).find(R"("x":1.5,"y":null,)") != std::string::npos);
  const std::string none = sensor_json(silent("mast"));
  CHECK(none.find(R"("x":null,"y":null,"tilt":null,"age_ms":null,)") != std::string::npos);
  CHECK(none.find(R"("online":false,"stale":true,)") != std::string::npos);
  CHECK(none.find(R"("polls_per_s":null,)") != std::string::npos);
  CHECK(none.find(R"("naks":{},"line_seconds":0,"line_share":null,"settings":{}})") != std::string::npos);
  CHECK(json_number(NAN).is_null());
  CHECK(json_number(INFINITY).is_null());
  SensorStatus broken = boom();
  broken.x = NAN;
  broken.y = -INFINITY;
  CHECK(sensor_json(broken).find(R"("x":null,"y":null,)") != std::string::npos);
}

TEST_CASE("status JSON: names are escaped as JSON strings") {
  SensorStatus odd = boom();
  odd.name = "a\"b\\c\nd\te\x01";
  CHECK(sensor_json(odd).starts_with(R"({"name":"a\"b\\c\nd\te\u0001",)"));
  odd.name = "Neigung °";
  CHECK(sensor_json(odd).starts_with("{\"name\":\"Neigung °\","));
}

TEST_CASE("status JSON: bytes a sensor sent that are not UTF-8 become U+FFFD, not an error") {
  SensorStatus odd = boom();
  odd.firmware = "A\xff" "8";
  CHECK(sensor_json(odd).find("\"firmware\":\"A\xef\xbf\xbd" "8\",") != std::string::npos);
}

TEST_CASE("status JSON: a reading keeps its shortest decimal form, a whole number no fraction") {
  SensorStatus s = boom();
  s.x = 12.345;
  s.y = -0.1;
  s.tilt = 1e-05;
  s.line_seconds = 3.0;
  const std::string text = sensor_json(s);
  CHECK(text.find(R"("x":12.345,"y":-0.1,"tilt":1e-05,)") != std::string::npos);
  CHECK(text.find(R"("line_seconds":3,)") != std::string::npos);
}

TEST_CASE("status JSON: the sensor and bus lists are arrays") {
  CHECK(sensors_json({}) == "[]");
  const std::string two = sensors_json(plant().sensors);
  CHECK(two.front() == '[');
  CHECK(two.find("},{\"name\":\"mast\"") != std::string::npos);
  CHECK(buses_json(plant().buses) ==
        R"([{"name":"line1","port":"/dev/ttyUSB0","baud":125000,"protocol":"p1","polls":12,)"
        R"("writes":1,"forwarded":0,"machine_held":3,"overloaded":1,"busy_seconds":1.25,)"
        R"("polls_per_s":9.5,"utilisation":0.5,"restarts":0,)"
        R"("failures":{"polls_failed":0,"timeout":0,"checksum":0,"io_error":0,"late_reply":0},)"
        R"("failures_10min":null}])");
  CHECK(buses_json({bus("line2", "/dev/ttyUSB1", 9600)}).find(R"("polls_per_s":null,"utilisation":null,)") != std::string::npos);
}

TEST_CASE("status JSON: failures in the last 10 minutes beside those since start") {
  SensorStatus s = boom();
  s.recent_failures = FailureCounts{1, 0, 0, 0, 1};
  CHECK(sensor_json(s).find(
            R"("failures_10min":{"polls_failed":1,"timeout":0,"checksum":0,"io_error":0,"late_reply":1},)") !=
        std::string::npos);
  BusStatus b = bus("line2", "/dev/ttyUSB1", 9600);
  b.failures = FailureCounts{2, 3, 1, 0, 4};
  b.recent_failures = FailureCounts{};
  CHECK(buses_json({b}).find(
            R"("failures":{"polls_failed":2,"timeout":3,"checksum":1,"io_error":0,"late_reply":4},)"
            R"("failures_10min":{"polls_failed":0,)") != std::string::npos);
}

TEST_CASE("metrics: label values escape backslash, quote and line feed") {
  CHECK(metrics_label_value("a\\b\"c\nd") == "a\\\\b\\\"c\\nd");
  GatewayStatus status = plant();
  status.sensors[0].name = "odd\"name";
  const std::string text = metrics_text(status);
  CHECK(text.find(R"(tiltgate_sensor_online{sensor="odd\"name",bus="line1",unit="3"} 1)") !=
        std::string::npos);
}

TEST_CASE("metrics: each sensor's angles, online, age and polls by result") {
  const std::string text = metrics_text(plant());
  const std::string labels = R"(sensor="boom",bus="line1",unit="3")";
  CHECK(text.find("tiltgate_angle_degrees{" + labels + ",axis=\"x\"} 1.5\n") != std::string::npos);
  CHECK(text.find("tiltgate_angle_degrees{" + labels + ",axis=\"y\"} -2.25\n") != std::string::npos);
  CHECK(text.find("tiltgate_reading_age_seconds{" + labels + "} 0.04\n") != std::string::npos);
  CHECK(text.find("tiltgate_polls_total{" + labels + ",result=\"ok\"} 10\n") != std::string::npos);
  CHECK(text.find("tiltgate_polls_total{" + labels + ",result=\"failed\"} 2\n") != std::string::npos);
  CHECK(text.find("tiltgate_bus_polls_total{bus=\"line1\"} 12\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_clients 2\n") != std::string::npos);
  CHECK(text.find("tiltgate_process_start_time_seconds 1700000000.5\n") != std::string::npos);
  // A sensor without a reading has no angle or age series (not NaN), but is offline.
  CHECK(text.find("sensor=\"mast\",bus=\"line1\",unit=\"4\",axis") == std::string::npos);
  CHECK(text.find("tiltgate_reading_age_seconds{sensor=\"mast\"") == std::string::npos);
  CHECK(text.find("tiltgate_sensor_online{sensor=\"mast\",bus=\"line1\",unit=\"4\"} 0\n") !=
        std::string::npos);
}

TEST_CASE("metrics: each sensor's line time and its share of the line, none before counted") {
  const std::string text = metrics_text(plant());
  const std::string labels = R"(sensor="boom",bus="line1",unit="3")";
  CHECK(text.find("tiltgate_sensor_line_seconds_total{" + labels + "} 12.5\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_line_share_ratio{" + labels + "} 0.031\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_line_seconds_total{sensor=\"mast\",bus=\"line1\",unit=\"4\"} 0\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_line_share_ratio{sensor=\"mast\"") == std::string::npos);
  CHECK(text.find("# TYPE tiltgate_sensor_line_seconds_total counter\n") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_sensor_line_share_ratio gauge\n") != std::string::npos);
}

TEST_CASE("metrics: failures by reason, NAKs by code, bus use and Modbus requests by function") {
  const std::string text = metrics_text(plant());
  const std::string labels = R"(sensor="boom",bus="line1",unit="3")";
  CHECK(text.find("tiltgate_sensor_failures_total{" + labels + ",reason=\"timeout\"} 3\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_failures_total{" + labels + ",reason=\"checksum\"} 1\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_failures_total{" + labels + ",reason=\"io_error\"} 0\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_late_replies_total{" + labels + "} 4\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_slowest_reply_seconds{" + labels + "} 0.007\n") !=
        std::string::npos);
  CHECK(text.find("# TYPE tiltgate_sensor_reply_seconds histogram\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_bucket{" + labels + ",le=\"0.001\"} 0\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_bucket{" + labels + ",le=\"0.002\"} 8\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_bucket{" + labels + ",le=\"0.01\"} 10\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_bucket{" + labels + ",le=\"+Inf\"} 10\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_sum{" + labels + "} 0.03\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_reply_seconds_count{" + labels + "} 10\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_naks_total{" + labels + ",code=\"3\"} 2\n") != std::string::npos);
  CHECK(text.find("tiltgate_sensor_naks_total{" + labels + ",code=\"5\"} 1\n") != std::string::npos);
  // Only codes seen: the silent sensor has no NAK series.
  CHECK(text.find("tiltgate_sensor_naks_total{sensor=\"mast\"") == std::string::npos);
  CHECK(text.find("tiltgate_bus_busy_seconds_total{bus=\"line1\"} 1.25\n") != std::string::npos);
  CHECK(text.find("tiltgate_bus_utilisation_ratio{bus=\"line1\"} 0.5\n") != std::string::npos);
  CHECK(text.find("tiltgate_bus_machine_held_total{bus=\"line1\"} 3\n") != std::string::npos);
  CHECK(text.find("tiltgate_bus_overloaded_total{bus=\"line1\"} 1\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_requests_total{function=\"03\"} 7\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_requests_total{function=\"2B\"} 1\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_exceptions_total{function=\"03\",code=\"02\"} 1\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_modbus_connections_total 6\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_connections_refused_total 1\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_connections_replaced_total 3\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_connections_denied_total 4\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_writes_denied_total 5\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_connections_denied_total 2\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_tls_refused_total 6\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_max_requests_per_second 20000\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_max_client_requests_per_second 5000\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_requests_delayed_total 11\n") != std::string::npos);
  CHECK(text.find("tiltgate_modbus_request_delay_seconds_total 0.25\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_max_requests_per_second 400\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_max_client_requests_per_second 100\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_requests_delayed_total 7\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_request_delay_seconds_total 0.5\n") != std::string::npos);
}

TEST_CASE("JSON: /api/modbus counts the connections and who was kept out") {
  CHECK(modbus_json(plant()) ==
        "{\"clients\":2,\"connections\":6,\"refused\":1,\"replaced\":3,\"denied\":4,"
        "\"writes_denied\":5,\"tls_refused\":6,\"max_requests_per_s\":20000,"
        "\"max_client_requests_per_s\":5000,\"requests_delayed\":11,"
        "\"request_delay_seconds\":0.25,\"http_denied\":2}");
}

TEST_CASE("metrics: the MQTT feed's series only when [mqtt] is on") {
  GatewayStatus status = plant();
  CHECK(metrics_text(status).find("tiltgate_mqtt_") == std::string::npos);
  status.mqtt = MqttStats{12, 3, 5, true, 1, {}};
  const std::string text = metrics_text(status);
  CHECK(text.find("tiltgate_mqtt_connected 1\n") != std::string::npos);
  CHECK(text.find("tiltgate_mqtt_published_total 12\n") != std::string::npos);
  CHECK(text.find("tiltgate_mqtt_dropped_total 3\n") != std::string::npos);
  CHECK(text.find("tiltgate_mqtt_backlog_messages 5\n") != std::string::npos);
  CHECK(text.find("tiltgate_mqtt_reconnects_total 1\n") != std::string::npos);
}

TEST_CASE("metrics: the Sparkplug edge node's series only when [sparkplug] is on, its store's "
          "labelled by feed") {
  GatewayStatus status = plant();
  CHECK(metrics_text(status).find("tiltgate_sparkplug_") == std::string::npos);
  CHECK(metrics_text(status).find("tiltgate_store_") == std::string::npos);
  status.sparkplug = SparkplugStats{true, 42, 1, 2, 3, 4, 5};
  status.stores.push_back(StoreStats{"sparkplug", 4096, 7, 8, 9, 10});
  const std::string text = metrics_text(status);
  CHECK(text.find("tiltgate_sparkplug_connected 1\n") != std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_published_total 42\n") != std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_commands_total{result=\"rebirth\"} 1\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_commands_total{result=\"write\"} 2\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_commands_total{result=\"refused\"} 3\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_commands_total{result=\"ignored\"} 4\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_sparkplug_commands_total{result=\"malformed\"} 5\n") !=
        std::string::npos);
  CHECK(text.find("tiltgate_store_bytes{feed=\"sparkplug\"} 4096\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_records{feed=\"sparkplug\"} 7\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_dropped_total{feed=\"sparkplug\"} 8\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_replayed_total{feed=\"sparkplug\"} 9\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_lost_total{feed=\"sparkplug\"} 10\n") != std::string::npos);
}

TEST_CASE("metrics: every sample follows a HELP and TYPE of its own name, in the 0.0.4 format") {
  const std::regex help(R"(# HELP (tiltgate_[a-z_]+) .+)");
  const std::regex type(R"(# TYPE (tiltgate_[a-z_]+) (gauge|counter|histogram))");
  const std::regex sample(
      R"((tiltgate_[a-z_]+)(\{([a-z_]+="([^"\\\n]|\\[\\"n])*")(,[a-z_]+="([^"\\\n]|\\[\\"n])*")*\})? )"
      R"((-?[0-9.]+(e[-+]?[0-9]+)?|NaN|[+-]Inf))");
  GatewayStatus status = plant();
  status.mqtt = MqttStats{12, 3, 5, true, 1, {}};
  status.sparkplug = SparkplugStats{true, 42, 1, 2, 3, 4, 5};
  status.stores.push_back(StoreStats{"sparkplug", 4096, 7, 8, 9});
  std::istringstream lines(metrics_text(status));
  std::string line, helped, typed, kind;
  std::set<std::string> families;
  int samples = 0;
  while (std::getline(lines, line)) {
    INFO(line);
    std::smatch m;
    if (std::regex_match(line, m, help)) {
      helped = m[1];
      CHECK(families.insert(helped).second);  // each family once
    } else if (std::regex_match(line, m, type)) {
      typed = m[1];
      kind = m[2];
      CHECK(typed == helped);
      if (m[2] == "counter") CHECK(typed.ends_with("_total"));
    } else {
      REQUIRE(std::regex_match(line, m, sample));
      if (kind == "histogram")  // its series: _bucket (with le), _sum and _count
        CHECK((m[1] == typed + "_bucket" || m[1] == typed + "_sum" || m[1] == typed + "_count"));
      else
        CHECK(m[1] == typed);
      ++samples;
    }
  }
  CHECK(samples > 10);
}

TEST_CASE("HTTP routes: read-only, known endpoints only, unknown sensors 404") {
  int taken = 0;
  const StatusSource status = [&] {
    ++taken;
    return plant();
  };
  CHECK(route_http("GET", "/healthz", status).body == "ok\n");
  CHECK(taken == 0);  // a health check does not copy the status
  const HttpReply post = route_http("POST", "/api/sensors", status);
  CHECK(post.status == 405);
  CHECK(post.allow_get);
  CHECK(route_http("PUT", "/healthz", status).status == 405);
  CHECK(route_http("GET", "/nothing", status).status == 404);
  CHECK(route_http("GET", "/api/sensors/nobody", status).status == 404);
  const HttpReply one = route_http("GET", "/api/sensors/boom?x=1", status);
  CHECK(one.status == 200);
  CHECK(one.content_type == "application/json");
  CHECK(one.body == sensor_json(boom()));
  CHECK(route_http("GET", "/api/sensors/m%61st", status).body == sensor_json(silent("mast")));
  CHECK(route_http("GET", "/api/sensors/m%6", status).status == 404);
  CHECK(route_http("GET", "/api/buses", status).body == buses_json(plant().buses));
  const HttpReply metrics = route_http("GET", "/metrics", status);
  CHECK(metrics.content_type == kMetricsContentType);
  CHECK(metrics.body == metrics_text(plant()));
}

TEST_CASE("metrics: HTTP clients closed for cause are counted by reason") {
  const std::string text = metrics_text(plant());
  CHECK(text.find("# TYPE tiltgate_http_clients_closed_total counter\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"refused\"} 7\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"replaced\"} 8\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"timeout\"} 9\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"bad_request\"} 10\n") !=
        std::string::npos);
}
