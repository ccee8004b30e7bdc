// The status API's JSON, built from a fixed GatewayStatus: fields and their order, nulls where
// a value is missing, and escaping of names that need it.
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

TEST_CASE("status JSON: a sensor with a reading shows every field") {
  CHECK(sensor_json(boom()) ==
        R"({"name":"boom","bus":"line1","unit_id":3,"address":223,"model":"m1",)"
        R"("serial":"962285","firmware":"1.2","configured_serial":null,"wrong_device":false,)"
        R"("online":true,"stale":false,"x":1.5,"y":-2.25,)"
        R"("tilt":2.7,"age_ms":40,"alarms":5,"alarms_danger":0,"alarms_latched":0,)"
        R"("relative_x":null,"relative_y":null,"displacement_x_mm":null,)"
        R"("displacement_y_mm":null,"displacement_mm":null,"temperature":null,)"
        R"("reading_time":null,"clock_synchronised":true,)"
        R"("polls_ok":10,"polls_failed":2,"polls_per_s":4.5,)"
        R"("failures":{"timeout":3,"checksum":1,"io_error":0,"late_reply":4},)"
        R"("failures_10min":null,)"
        R"("exchanges":{"requests":14,"replies":10,"garbled":1,"no_reply":3,"exceptions":3,)"
        R"("naks":2,"busy":1,"bytes_out":140,"bytes_in":200,"overruns":0,"uart_errors":2},)"
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
        R"("failures_10min":null,)"
        R"("exchanges":{"requests":0,"replies":0,"garbled":0,"no_reply":0,"exceptions":0,)"
        R"("naks":0,"busy":0,"bytes_out":0,"bytes_in":0,"overruns":0,"uart_errors":0},)"
        R"("bytes_out":500,"bytes_in":706,"stray_bytes":6,"reopens":0,)"
        R"("black_box":{"keep_s":60,"frames":40,"bytes":9000,"dropped":2},"hint":null}])");
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

TEST_CASE("JSON: /api/modbus counts the connections and who was kept out") {
  CHECK(modbus_json(plant()) ==
        "{\"clients\":2,\"connections\":6,\"refused\":1,\"replaced\":3,\"denied\":4,"
        "\"writes_denied\":5,\"tls_refused\":6,\"max_requests_per_s\":20000,"
        "\"max_client_requests_per_s\":5000,\"requests_delayed\":11,"
        "\"request_delay_seconds\":0.25,\"http_denied\":2}");
}

namespace {

// A standby that has heard the active gateway's request 180 ms ago, as Gateway::status() fills
// it in.
RedundancyStatus listening_standby() {
  RedundancyStatus pair;
  pair.configured_role = "standby";
  pair.active = false;
  pair.takeovers = 2;
  pair.step_downs = 1;
  pair.since_seconds = 1700000100;
  pair.reason = "the primary polls the lines";
  pair.peer = "10.0.0.5:502";
  pair.takeover_ms = 2000;
  pair.failback = true;
  pair.last_request_heard_ms = 180;
  return pair;
}

}  // namespace

TEST_CASE("JSON: /api/status of a gateway without [redundancy] is active, with its uptime") {
  GatewayStatus status = plant();  // started at 1700000000.5
  status.loaded_at = "2026-12-02 05:10:22";
  const Json state = Json::parse(gateway_state_json(status, 1700000100.25));
  CHECK(state["role"] == "active");
  CHECK(state["redundancy"].is_null());
  CHECK(state["uptime_s"] == 99);  // whole seconds
  CHECK(state["loaded_at"] == "2026-12-02 05:10:22");
  CHECK(state["version"].is_string());
  CHECK_FALSE(state["version"].get<std::string>().empty());
  std::vector<std::string> keys;
  for (const auto& item : state.items()) keys.push_back(item.key());
  CHECK(keys == std::vector<std::string>{"role", "redundancy", "uptime_s", "loaded_at", "version",
                                          "clock"});
  // Before anyone says when the configuration was loaded: null, not "".
  CHECK(Json::parse(gateway_state_json(plant(), 0))["loaded_at"].is_null());
  CHECK(Json::parse(gateway_state_json(plant(), 0))["uptime_s"] == 0);  // a clock set back
}

TEST_CASE("JSON: /api/status of a standby shows its pair, and which of the two polls now") {
  GatewayStatus status = plant();
  status.redundancy = listening_standby();
  const std::string text = gateway_state_json(status, 1700000200);
  CHECK(text.starts_with(
      R"({"role":"standby","redundancy":{"configured_role":"standby","active":false,)"
      R"("takeovers":2,"step_downs":1,"since":1700000100,"reason":"the primary polls the lines",)"
      R"("peer":"10.0.0.5:502","takeover_ms":2000,"failback":true,"last_request_heard_ms":180},)"
      R"("uptime_s":199,)"));

  status.redundancy->last_request_heard_ms.reset();  // nothing heard yet
  CHECK(Json::parse(gateway_state_json(status, 0))["redundancy"]["last_request_heard_ms"].is_null());

  status.redundancy->active = true;  // taken over: the standby by configuration is active now
  const Json taken = Json::parse(gateway_state_json(status, 0));
  CHECK(taken["role"] == "active");
  CHECK(taken["redundancy"]["configured_role"] == "standby");
}

TEST_CASE("JSON: /api/status shows the clock: synchronised with its error bound in ms, or null") {
  GatewayStatus status = plant();
  status.clock = ClockState{true, 12.345, 1.5, ClockProblem::none};
  CHECK(Json::parse(gateway_state_json(status, 0))["clock"] ==
        Json::parse(R"({"synchronised":true,"error_ms":12.345})"));
  CHECK(gateway_state_json(status, 0).ends_with(
      R"("clock":{"synchronised":true,"error_ms":12.345}})"));
  status.clock = ClockState{false, std::nullopt, std::nullopt, ClockProblem::unbounded};
  CHECK(gateway_state_json(status, 0)
            .ends_with(R"("clock":{"synchronised":false,"error_ms":null}})"));
}

TEST_CASE("status JSON: a sensor's baseline, displacement, temperature, alarm levels and reading time") {
  SensorStatus s = boom();
  s.alarms_danger = 1;
  s.alarms_latched = 5;
  s.relative_x = 0.25;
  s.relative_y = -0.5;
  s.displacement_x_mm = 43.62;
  s.displacement_y_mm = 0.0;
  s.displacement_mm = 43.62;
  s.temperature = -3.5;
  s.reading_unix_ms = 1796638502250;
  s.clock_synchronised = false;
  const std::string text = sensor_json(s);
  CHECK(text.find(R"("alarms":5,"alarms_danger":1,"alarms_latched":5,)"
                  R"("relative_x":0.25,"relative_y":-0.5,"displacement_x_mm":43.62,)"
                  R"("displacement_y_mm":0,"displacement_mm":43.62,"temperature":-3.5,)"
                  R"("reading_time":"2026-12-07T10:15:02.250Z",)"
                  R"("clock_synchronised":false,)") != std::string::npos);
}
