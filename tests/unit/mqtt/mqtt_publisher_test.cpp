// The MQTT feed's decisions: when a sensor's state is due (interval, on_change_deg, online), and
// when its info is sent again.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "mqtt/mqtt_publisher.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

const Clock::time_point t0 = Clock::time_point{} + 1h;

StateSample at(double x, std::uint64_t readings = 1, bool online = true) {
  return {x, 0.0, online, readings};
}

MqttPacing pacing(double on_change_deg) {
  MqttPacing p;
  p.interval = 1000ms;
  p.on_change_deg = on_change_deg;
  p.min_spacing = 100ms;
  return p;
}

SensorStatus sensor(std::string name, double x) {
  SensorStatus s;
  s.name = std::move(name);
  s.bus = "line1";
  s.online = true;
  s.x = x;
  s.y = 0.0;
  s.age_ms = 0;
  return s;
}

std::vector<std::string> topics(const std::vector<MqttMessage>& messages) {
  std::vector<std::string> out;
  for (const MqttMessage& message : messages) out.push_back(message.topic);
  return out;
}

}  // namespace

TEST_CASE("mqtt pacing: the first sample is due, then again once the interval has passed") {
  StatePacer pacer(pacing(0.01));
  CHECK(pacer.due(at(1.0), t0));
  pacer.published(at(1.0), t0);
  CHECK_FALSE(pacer.due(at(1.0, 2), t0 + 999ms));
  CHECK(pacer.due(at(1.0, 2), t0 + 1000ms));
}

TEST_CASE("mqtt pacing: an angle moved by on_change_deg is due after min_spacing, less is not") {
  StatePacer pacer(pacing(0.5));
  pacer.published(at(1.0), t0);
  CHECK_FALSE(pacer.due(at(1.4), t0 + 200ms));
  CHECK_FALSE(pacer.due(at(1.5), t0 + 50ms));  // within min_spacing
  CHECK(pacer.due(at(1.5), t0 + 100ms));
  CHECK(pacer.due(at(0.5), t0 + 100ms));
  // y counts as much as x.
  CHECK(pacer.due(StateSample{1.0, 0.5, true, 2}, t0 + 100ms));
}

TEST_CASE("mqtt pacing: the change is measured from the last published angle, not the last seen") {
  StatePacer pacer(pacing(0.5));
  pacer.published(at(1.0), t0);
  CHECK_FALSE(pacer.due(at(1.3), t0 + 200ms));
  CHECK(pacer.due(at(1.6), t0 + 300ms));  // 0.6 from 1.0, though 0.3 from the sample before
}

TEST_CASE("mqtt pacing: on_change_deg 0 sends every new reading, spaced by min_spacing") {
  StatePacer pacer(pacing(0.0));
  pacer.published(at(1.0, 1), t0);
  CHECK_FALSE(pacer.due(at(1.0, 1), t0 + 300ms));  // no new reading
  CHECK_FALSE(pacer.due(at(1.0, 2), t0 + 50ms));
  CHECK(pacer.due(at(1.0, 2), t0 + 100ms));
}

TEST_CASE("mqtt pacing: a sensor going offline, or its first reading, is due at once") {
  StatePacer pacer(pacing(10.0));
  pacer.published(at(1.0), t0);
  CHECK(pacer.due(at(1.0, 1, false), t0 + 10ms));
  StatePacer fresh(pacing(10.0));
  fresh.published(StateSample{std::nullopt, std::nullopt, false, 0}, t0);
  CHECK(fresh.due(StateSample{1.0, 0.0, false, 1}, t0 + 100ms));
}

TEST_CASE("mqtt pacing: a wrong device found, or gone, is due at once") {
  StatePacer pacer(pacing(10.0));
  pacer.published(at(1.0), t0);
  CHECK(pacer.due(StateSample{1.0, 0.0, true, 1, true}, t0 + 10ms));
  pacer.published(StateSample{1.0, 0.0, true, 1, true}, t0);
  CHECK(pacer.due(StateSample{1.0, 0.0, true, 1, false}, t0 + 10ms));
}

TEST_CASE("mqtt pacing: the gateway's clock lost, or back, is due at once") {
  StatePacer pacer(pacing(10.0));
  pacer.published(at(1.0), t0);
  CHECK_FALSE(pacer.due(StateSample{1.0, 0.0, true, 1, false, false}, t0 + 10ms));
  CHECK(pacer.due(StateSample{1.0, 0.0, true, 1, false, true}, t0 + 10ms));
}

TEST_CASE("mqtt publisher: each state carries the gateway's clock, its change sent at once") {
  MqttPublisher publisher({"gw", pacing(0.5)});
  GatewayStatus status;
  status.sensors = {sensor("boom", 1.0)};
  const std::vector<MqttMessage> first = publisher.take(status, t0, 1000);
  REQUIRE(first.size() == 2);
  CHECK(first[1].payload.ends_with(R"("clock_synchronised":false,"clock_error_ms":null})"));
  status.clock = ClockState{true, 3.5, 0.5, ClockProblem::none};
  const std::vector<MqttMessage> synced = publisher.take(status, t0 + 10ms, 1010);
  REQUIRE(topics(synced) == std::vector<std::string>{"gw/boom/state"});
  CHECK(synced[0].payload.ends_with(R"("clock_synchronised":true,"clock_error_ms":3.5})"));
}

TEST_CASE("mqtt publisher: each sensor's info (retained) then state, then states as they come due") {
  MqttPublisher publisher({"gw", pacing(0.5)});
  GatewayStatus status;
  status.sensors = {sensor("boom", 1.0), sensor("mast", 2.0)};
  const std::vector<MqttMessage> first = publisher.take(status, t0, 1000);
  REQUIRE(first.size() == 4);
  CHECK(first[0].retain);
  CHECK_FALSE(first[1].retain);
  CHECK(first[1].time_unix_ms == 1000);
  CHECK(topics(first) ==
        std::vector<std::string>{"gw/boom/info", "gw/boom/state", "gw/mast/info", "gw/mast/state"});

  status.sensors[1].x = 3.0;  // mast moved; boom did not
  CHECK(topics(publisher.take(status, t0 + 200ms, 1200)) ==
        std::vector<std::string>{"gw/mast/state"});
  // boom's interval is over
  CHECK(topics(publisher.take(status, t0 + 1100ms, 2100)) ==
        std::vector<std::string>{"gw/boom/state"});
}

TEST_CASE("mqtt publisher: info is sent again when it changes, and after forget_info") {
  MqttPublisher publisher({"gw", pacing(0.5)});
  GatewayStatus status;
  status.sensors = {sensor("boom", 1.0)};
  publisher.take(status, t0, 1000);
  status.sensors[0].serial = "9600223";  // arrives after the first poll
  const std::vector<MqttMessage> changed = publisher.take(status, t0 + 10ms, 1010);
  REQUIRE(changed.size() == 1);
  CHECK(changed[0].payload.find("9600223") != std::string::npos);
  CHECK(publisher.take(status, t0 + 20ms, 1020).empty());
  publisher.forget_info();
  CHECK(topics(publisher.take(status, t0 + 30ms, 1030)) ==
        std::vector<std::string>{"gw/boom/info"});
}
