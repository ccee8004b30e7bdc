// The /metrics text, built from a fixed GatewayStatus: each family's HELP and TYPE, its samples
// and labels, escaping, and the series of the services that are on.
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
#include "unit/status/status_fixture.h"

using namespace tiltgate;
using namespace tiltgate::test;

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
  status.redundancy = RedundancyStatus{};
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

TEST_CASE("metrics: HTTP clients closed for cause are counted by reason") {
  const std::string text = metrics_text(plant());
  CHECK(text.find("# TYPE tiltgate_http_clients_closed_total counter\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"refused\"} 7\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"replaced\"} 8\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"timeout\"} 9\n") != std::string::npos);
  CHECK(text.find("tiltgate_http_clients_closed_total{reason=\"bad_request\"} 10\n") !=
        std::string::npos);
}

TEST_CASE("metrics: a sensor's exchanges attempt by attempt, and what each bus's line carried") {
  const std::string text = metrics_text(plant());
  const std::string labels = R"(sensor="boom",bus="line1",unit="3")";
  const auto has = [&](const std::string& line) { return text.find(line + "\n") != std::string::npos; };
  CHECK(has("tiltgate_sensor_requests_total{" + labels + "} 14"));
  CHECK(has("tiltgate_sensor_replies_total{" + labels + "} 10"));
  CHECK(has("tiltgate_sensor_garbled_replies_total{" + labels + "} 1"));
  CHECK(has("tiltgate_sensor_no_reply_total{" + labels + "} 3"));
  CHECK(has("tiltgate_sensor_busy_total{" + labels + "} 1"));
  CHECK(has("tiltgate_sensor_overruns_total{" + labels + "} 0"));
  CHECK(has("tiltgate_sensor_uart_errors_total{" + labels + "} 2"));
  CHECK(has("tiltgate_sensor_bytes_total{" + labels + ",direction=\"out\"} 140"));
  CHECK(has("tiltgate_sensor_bytes_total{" + labels + ",direction=\"in\"} 200"));
  CHECK(has("# TYPE tiltgate_sensor_requests_total counter"));
  CHECK(has("tiltgate_bus_bytes_total{bus=\"line1\",direction=\"out\"} 500"));
  CHECK(has("tiltgate_bus_bytes_total{bus=\"line1\",direction=\"in\"} 706"));
  CHECK(has("tiltgate_bus_stray_bytes_total{bus=\"line1\"} 6"));
  CHECK(has("tiltgate_bus_black_box_bytes{bus=\"line1\"} 9000"));
  CHECK(has("# TYPE tiltgate_bus_black_box_bytes gauge"));
  CHECK(has("tiltgate_bus_black_box_dropped_total{bus=\"line1\"} 2"));
}

TEST_CASE("metrics: the redundant pair's series only when [redundancy] is configured") {
  GatewayStatus status = plant();
  CHECK(metrics_text(status).find("tiltgate_redundancy_") == std::string::npos);
  status.redundancy = RedundancyStatus{};
  status.redundancy->configured_role = "primary";
  status.redundancy->active = true;
  status.redundancy->takeovers = 3;
  std::string text = metrics_text(status);
  CHECK(text.find("# HELP tiltgate_redundancy_active ") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_redundancy_active gauge\ntiltgate_redundancy_active 1\n") !=
        std::string::npos);
  CHECK(text.find("# HELP tiltgate_redundancy_takeovers_total ") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_redundancy_takeovers_total counter\n"
                  "tiltgate_redundancy_takeovers_total 3\n") != std::string::npos);
  status.redundancy->active = false;  // stepped down: the standby, listening
  text = metrics_text(status);
  CHECK(text.find("tiltgate_redundancy_active 0\n") != std::string::npos);
}

TEST_CASE("metrics: the clock's state, and its error bound in seconds only while synchronised") {
  GatewayStatus status = plant();
  status.clock = ClockState{true, 12.5, 1.0, ClockProblem::none};
  std::string text = metrics_text(status);
  CHECK(text.find("# HELP tiltgate_clock_synchronised ") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_clock_synchronised gauge\ntiltgate_clock_synchronised 1\n") !=
        std::string::npos);
  CHECK(text.find("# HELP tiltgate_clock_error_seconds ") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_clock_error_seconds gauge\n"
                  "tiltgate_clock_error_seconds 0.0125\n") != std::string::npos);
  status.clock = ClockState{false, std::nullopt, std::nullopt, ClockProblem::unbounded};
  text = metrics_text(status);
  CHECK(text.find("tiltgate_clock_synchronised 0\n") != std::string::npos);
  // No bound, no sample (not NaN); the family's HELP and TYPE stay.
  CHECK(text.find("# TYPE tiltgate_clock_error_seconds gauge\n# HELP") != std::string::npos);
  CHECK(text.find("\ntiltgate_clock_error_seconds ") == std::string::npos);
}
