// The edge node's data by exception, device deaths and rebirths (sparkplug/edge_node_session.h):
// when a DDATA goes out, what it holds, and what happens to a sensor that falls silent.
#include <doctest/doctest.h>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

// boom is the first device: 256 + the metric's number (sparkplug/device_metrics.h).
constexpr std::uint64_t kBoomX = 257, kBoomY = 258, kBoomTilt = 259, kBoomStatus = 260,
                        kBoomStale = 262, kBoomAlarms = 263, kBoomAge = 264,
                        kBoomRelativeX = 269, kBoomRelativeY = 270;

std::vector<Publish> step(LiveSession& live, const DeviceSample& sample, std::int64_t ms) {
  const DeviceSample samples[] = {sample};
  return publishes(live.session.update(samples, at(ms)));
}

std::vector<std::uint64_t> aliases(const Payload& payload) {
  std::vector<std::uint64_t> out;
  for (const Metric& m : payload.metrics) out.push_back(m.alias.value_or(0));
  return out;
}

}  // namespace

TEST_CASE("tck-id-payloads-alias-data-cmd-requirement: DDATA names its metrics by alias only") {
  LiveSession live;
  const auto out = step(live, boom(2.0, 0.0, 200), 200);
  REQUIRE(out.size() == 1);
  CHECK(out[0].topic == "spBv1.0/plant/DDATA/gw1/boom");
  CHECK(out[0].qos == 0);  // tck-id-topics-ddata-mqtt
  CHECK_FALSE(out[0].retain);
  for (const Metric& m : out[0].payload.metrics) {
    CHECK(m.name.empty());
    CHECK(m.alias.has_value());
    CHECK(m.timestamp == static_cast<std::uint64_t>(kUnixStart + 200));
    CHECK_FALSE(m.is_historical);
    CHECK(m.properties.empty());
  }
  CHECK(find_alias(out[0].payload, kBoomX)->value == Value{2.0});
}

TEST_CASE("a metric's time is never later than its message's, though the reading came after the sample was timed") {
  LiveSession live;
  // Sampled at 200 ms; the bus published a reading stamped 201 ms before the snapshot was read.
  const auto out = step(live, boom(2.0, 0.0, 201), 200);
  REQUIRE(out.size() == 1);
  CHECK(out[0].payload.timestamp == static_cast<std::uint64_t>(kUnixStart + 200));
  for (const Metric& m : out[0].payload.metrics)
    CHECK(m.timestamp == static_cast<std::uint64_t>(kUnixStart + 200));
}

TEST_CASE("tck-id-topics-ddata-payload: a DDATA when an angle moved by on_change_deg, with what changed only") {
  LiveSession live;  // on_change_deg 0.5, boom born at x 1.0 y 0.0
  CHECK(step(live, boom(1.4, 0.0, 200), 200).empty());
  CHECK(step(live, boom(1.0, 0.49, 300), 300).empty());
  const auto moved = step(live, boom(1.5, 0.0, 400), 400);
  REQUIRE(moved.size() == 1);
  // x and tilt moved, the age is the new reading's; y, status and the rest did not change.
  CHECK(aliases(moved[0].payload) == std::vector<std::uint64_t>{kBoomX, kBoomTilt});
  // Measured from the last DDATA (1.5), not from the samples in between.
  CHECK(step(live, boom(1.9, 0.0, 600), 600).empty());
  CHECK(step(live, boom(2.0, 0.0, 700), 700).size() == 1);
}

TEST_CASE("a DDATA never sooner than min_interval after the device's last message") {
  LiveSession live;  // the DBIRTH went at 0 ms; min_interval 100 ms
  CHECK(step(live, boom(5.0, 0.0, 50), 50).empty());
  const auto due = step(live, boom(5.0, 0.0, 50), 100);
  REQUIRE(due.size() == 1);
  CHECK(step(live, boom(9.0, 0.0, 150), 150).empty());
  CHECK(step(live, boom(9.0, 0.0, 150), 200).size() == 1);
}

TEST_CASE("a DDATA at least every max_interval, with the angles and the age though none changed") {
  LiveSession live;  // max_interval 10 s
  CHECK(step(live, boom(1.0, 0.0, 9000), 9999).empty());
  const auto heartbeat = step(live, boom(1.0, 0.0, 9900), 10000);
  REQUIRE(heartbeat.size() == 1);
  CHECK(aliases(heartbeat[0].payload) ==
        std::vector<std::uint64_t>{kBoomX, kBoomY, kBoomTilt, kBoomRelativeX, kBoomRelativeY,
                                  kBoomAge});
  CHECK(find_alias(heartbeat[0].payload, kBoomX)->timestamp ==
        static_cast<std::uint64_t>(kUnixStart + 9900));
}

TEST_CASE("a DDATA at once when status, stale or alarms change, holding what changed") {
  LiveSession live;
  auto s = boom(1.0, 0.0, 200);
  s.alarms = 0x0001;
  auto out = step(live, s, 200);
  REQUIRE(out.size() == 1);
  CHECK(aliases(out[0].payload) == std::vector<std::uint64_t>{kBoomAlarms});
  CHECK(find_alias(out[0].payload, kBoomAlarms)->value == Value{std::uint32_t{1}});
  s.status = 0x8000;
  s.stale = true;
  out = step(live, s, 300);
  REQUIRE(out.size() == 1);
  CHECK(aliases(out[0].payload) == std::vector<std::uint64_t>{kBoomStatus, kBoomStale});
}

TEST_CASE("a serial that arrives after the first poll goes out as a DDATA of Properties/serial") {
  LiveSession live;
  const DeviceSample samples[] = {mast(3.0, 200)};
  auto first = publishes(live.session.update(samples, at(200)));
  CHECK(first.empty());
  DeviceSample later = mast(3.0, 300);
  later.serial = "4360117";
  const DeviceSample next[] = {later};
  const auto out = publishes(live.session.update(next, at(300)));
  REQUIRE(out.size() == 1);
  CHECK(out[0].topic == "spBv1.0/plant/DDATA/gw1/mast");
  CHECK(find_alias(out[0].payload, 512 + 10)->value == Value{std::string("4360117")});
}

TEST_CASE("on_change_deg 0: a DDATA at every new reading, spaced by min_interval") {
  auto o = options();
  o.on_change_deg = 0;
  LiveSession live(o);
  CHECK(step(live, boom(1.0, 0.0, 0), 200).empty());  // the same reading as the DBIRTH's
  const auto same_angles = step(live, boom(1.0, 0.0, 150), 200);
  REQUIRE(same_angles.size() == 1);
  CHECK(aliases(same_angles[0].payload) ==
        std::vector<std::uint64_t>{kBoomX, kBoomY, kBoomTilt, kBoomRelativeX, kBoomRelativeY,
                                  kBoomAge});
  CHECK(step(live, boom(1.0, 0.0, 250), 250).empty());  // min_interval
  CHECK(step(live, boom(1.0, 0.0, 250), 300).size() == 1);
}

TEST_CASE("tck-id-operational-behavior-device-ddeath: a sensor gone offline gets a DDEATH, back, a new DBIRTH") {
  LiveSession live;
  const auto death = step(live, offline(boom(1.0, 0.0, 0)), 500);
  REQUIRE(death.size() == 1);
  CHECK(death[0].topic == "spBv1.0/plant/DDEATH/gw1/boom");
  CHECK(death[0].payload.seq == 3u);  // tck-id-topics-ddeath-seq-num
  CHECK(death[0].payload.metrics.empty());
  CHECK(death[0].payload.timestamp == static_cast<std::uint64_t>(kUnixStart + 500));
  CHECK(death[0].qos == 0);  // tck-id-topics-ddeath-mqtt
  // Still offline: nothing more, at any interval.
  CHECK(step(live, offline(boom(1.0, 0.0, 0)), 20000).empty());
  const auto birth = step(live, boom(2.0, 0.0, 21000), 21000);
  REQUIRE(birth.size() == 1);
  CHECK(birth[0].topic == "spBv1.0/plant/DBIRTH/gw1/boom");
  CHECK(birth[0].payload.seq == 4u);
  CHECK(find_metric(birth[0].payload, "angle_x")->value == Value{2.0});
}

TEST_CASE("a sensor offline at the CONNACK gets no DBIRTH until it answers") {
  auto session = make_session();
  const DeviceSample before[] = {boom(1.0), offline(mast(3.0))};
  (void)session.update(before, at(0));
  (void)session.begin_connect(at(0));
  CHECK(topics(session.on_connected(at(0))).back() == "spBv1.0/plant/DBIRTH/gw1/boom");
  const DeviceSample answered[] = {mast(3.0, 400)};
  const auto out = publishes(session.update(answered, at(400)));
  REQUIRE(out.size() == 1);
  CHECK(out[0].topic == "spBv1.0/plant/DBIRTH/gw1/mast");
}

TEST_CASE("a sensor whose metrics change shape (another model) gets a new DBIRTH, not a DDATA") {
  LiveSession live;
  auto s = boom(1.0, 0.0, 200);
  s.single_axis = true;
  s.angle_y.reset();
  const auto out = step(live, s, 200);
  REQUIRE(out.size() == 1);
  CHECK(out[0].topic == "spBv1.0/plant/DBIRTH/gw1/boom");
  CHECK(find_metric(out[0].payload, "angle_y") == nullptr);
}

TEST_CASE("samples of sensors the session does not know are ignored") {
  LiveSession live;
  auto stranger = boom(1.0);
  stranger.name = "crane";
  CHECK(step(live, stranger, 500).empty());
}

TEST_CASE("an angle that becomes unknown is sent as null") {
  LiveSession live;
  auto s = boom(1.0, 0.0, 200);
  s.angle_x.reset();
  const auto out = step(live, s, 200);
  REQUIRE(out.size() == 1);
  CHECK(find_alias(out[0].payload, kBoomX)->value == Value{});
}
