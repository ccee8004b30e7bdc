// The MQTT feed's topics and payloads (docs/northbound.md, "MQTT"), from a sensor's status copy.
#include <doctest/doctest.h>

#include "mqtt/mqtt_payload.h"

using namespace tiltgate;

namespace {

SensorStatus boom() {
  SensorStatus s;
  s.name = "boom";
  s.bus = "line1";
  s.unit_id = 3;
  s.address = 223;
  s.model = "h6";
  s.serial = "9600223";
  s.firmware = "Rev A.8";
  s.online = true;
  s.stale = false;
  s.x = 1.25;
  s.y = -0.5;
  s.tilt = 1.346;
  s.age_ms = 40;
  s.alarms = 2;
  return s;
}

// The gateway's clock, synchronised by a time service with a 12.5 ms bound.
ClockState synced() { return ClockState{true, 12.5, 1.0, ClockProblem::none}; }

}  // namespace

TEST_CASE("mqtt: topics are the prefix, the sensor's name and the kind") {
  CHECK(mqtt_state_topic("tiltgate/gw1", "boom") == "tiltgate/gw1/boom/state");
  CHECK(mqtt_burst_topic("tiltgate/gw1", "boom") == "tiltgate/gw1/boom/burst");
  CHECK(mqtt_info_topic("plant/north", "boom") == "plant/north/boom/info");
  CHECK(mqtt_status_topic("tiltgate/gw1") == "tiltgate/gw1/status");
}

TEST_CASE("mqtt: a state carries the reading's Unix time in ms, angles, online and alarms") {
  CHECK(mqtt_state_json(boom(), synced(), 1764640000040) ==
        R"({"ts":1764640000000,"x":1.25,"y":-0.5,"tilt":1.346,"relative_x":null,)"
        R"("relative_y":null,"displacement_mm":null,"temperature":null,"online":true,"stale":false,)"
        R"("age_ms":40,"alarms":2,"alarms_danger":0,"alarms_latched":0,"wrong_device":false,)"
        R"("reading_clock_synchronised":true,"clock_synchronised":true,"clock_error_ms":12.5})");
}

TEST_CASE("mqtt: a state's ts is the reading's own stamp, with its baseline, displacement and temperature") {
  SensorStatus s = boom();
  s.reading_unix_ms = 1764639999990;  // the reply's arrival, as the bus stamped it
  s.relative_x = 0.25;
  s.relative_y = -0.5;
  s.displacement_mm = 43.62;
  s.temperature = 21.5;
  s.alarms_danger = 1;
  s.alarms_latched = 3;
  s.clock_synchronised = false;
  CHECK(mqtt_state_json(s, synced(), 1764640000040) ==
        R"({"ts":1764639999990,"x":1.25,"y":-0.5,"tilt":1.346,"relative_x":0.25,)"
        R"("relative_y":-0.5,"displacement_mm":43.62,"temperature":21.5,"online":true,"stale":false,)"
        R"("age_ms":40,"alarms":2,"alarms_danger":1,"alarms_latched":3,"wrong_device":false,)"
        R"("reading_clock_synchronised":false,"clock_synchronised":true,"clock_error_ms":12.5})");
}

TEST_CASE("mqtt: a state before the first reading has null angles and the publish time") {
  SensorStatus s;
  s.name = "mast";
  CHECK(mqtt_state_json(s, synced(), 1764640000000) ==
        R"({"ts":1764640000000,"x":null,"y":null,"tilt":null,"relative_x":null,)"
        R"("relative_y":null,"displacement_mm":null,"temperature":null,"online":false,"stale":true,)"
        R"("age_ms":null,"alarms":0,"alarms_danger":0,"alarms_latched":0,"wrong_device":false,)"
        R"("reading_clock_synchronised":true,"clock_synchronised":true,"clock_error_ms":12.5})");
}

TEST_CASE("mqtt: a wrong device shows in the state, and the configured serial in the info") {
  SensorStatus s = boom();
  s.serial = "9600007";
  s.configured_serial = "9600223";
  s.wrong_device = true;
  CHECK(mqtt_state_json(s, synced(), 1000).find(R"("wrong_device":true,)") != std::string::npos);
  CHECK(mqtt_info_json(s).find(R"("serial":"9600007","firmware":"Rev A.8",)"
                               R"("configured_serial":"9600223"})") != std::string::npos);
}

TEST_CASE("mqtt: a single-axis sensor's state has y null") {
  SensorStatus s = boom();
  s.y.reset();
  CHECK(mqtt_state_json(s, synced(), 1000).find(R"("y":null)") != std::string::npos);
}

TEST_CASE("mqtt: info is the sensor's identity, strings escaped") {
  SensorStatus s = boom();
  CHECK(mqtt_info_json(s) ==
        R"({"name":"boom","bus":"line1","unit_id":3,"address":223,"model":"h6",)"
        R"("serial":"9600223","firmware":"Rev A.8","configured_serial":null})");
  s.firmware = "A\"8";
  CHECK(mqtt_info_json(s).find(R"("firmware":"A\"8")") != std::string::npos);
}

TEST_CASE("mqtt: a state says whether the gateway's clock was synchronised when it was made") {
  const ClockState unsynchronised{false, std::nullopt, std::nullopt, ClockProblem::unbounded};
  CHECK(mqtt_state_json(boom(), unsynchronised, 1000)
            .ends_with(R"(,"clock_synchronised":false,"clock_error_ms":null})"));
}

TEST_CASE("mqtt payload: a state kept for a replay says it is historical, and nothing else changes") {
  CHECK(mqtt_historical_state_json(R"({"ts":1,"x":null})") == R"({"ts":1,"x":null,"historical":true})");
}

TEST_CASE("mqtt: a burst's batch is historical, each sample with its own time") {
  monitoring::BurstBatch batch{7, "mast", "2026-12-07T10-15-02.250Z", "trigger", {}};
  FedSample s;
  s.unix_ms = 1796638502250;
  s.x = 2.5;
  s.tilt = 2.5;
  s.relative_x = 0.5;
  s.temperature_c = 21.5;
  s.alarms = 1;
  s.clock_synchronised = false;
  batch.samples.push_back(s);
  CHECK(mqtt_burst_json(batch) ==
        R"({"sensor":"mast","burst":"2026-12-07T10-15-02.250Z","phase":"trigger",)"
        R"("historical":true,"samples":[{"ts":1796638502250,"x":2.5,"y":null,"tilt":2.5,)"
        R"("relative_x":0.5,"relative_y":null,"displacement_mm":null,"temperature":21.5,)"
        R"("alarms":1,"clock_synchronised":false}]})");
}
