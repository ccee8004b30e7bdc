// Store-and-forward from the session's side (sparkplug/edge_node_session.h): what is kept while
// the data cannot be published, and how a kept DDATA is replayed after the births.
#include <doctest/doctest.h>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

std::vector<Keep> keep_outage(EdgeNodeSession& session) {
  std::vector<Keep> kept;
  for (int i = 1; i <= 3; ++i) {
    const DeviceSample samples[] = {boom(1.0 + i, 0.0, i * 1000), mast(3.0, i * 1000)};
    for (const Keep& k : all_of<Keep>(session.update(samples, at(i * 1000)))) kept.push_back(k);
  }
  return kept;
}

}  // namespace

TEST_CASE("while the broker is away, data is kept as historical DDATA by name, without seq, with the reading's time") {
  LiveSession live;
  live.session.on_connection_lost();
  const auto kept = keep_outage(live.session);
  REQUIRE(kept.size() == 3);  // boom moved 1° a second; mast did not change
  for (std::size_t i = 0; i < kept.size(); ++i) {
    CHECK(kept[i].topic == "spBv1.0/plant/DDATA/gw1/boom");
    CHECK(kept[i].time_unix_ms == kUnixStart + 1000 * static_cast<std::int64_t>(i + 1));
    CHECK_FALSE(kept[i].payload.seq.has_value());
    for (const Metric& m : kept[i].payload.metrics) {
      CHECK_FALSE(m.name.empty());
      CHECK_FALSE(m.alias.has_value());
      CHECK(m.is_historical);
      CHECK(m.timestamp == static_cast<std::uint64_t>(kept[i].time_unix_ms));
    }
  }
  CHECK(find_metric(kept[2].payload, "angle_x")->value == Value{4.0});
}

TEST_CASE("after the births a kept DDATA is replayed with aliases, historical, the next seq and its own timestamps") {
  LiveSession live;
  live.session.on_connection_lost();
  const auto kept = keep_outage(live.session);
  (void)live.session.begin_connect(at(5000));
  const auto births = publishes(live.session.on_connected(at(5000)));
  REQUIRE(births.size() == 3);  // NBIRTH 0, DBIRTH boom 1, DBIRTH mast 2
  std::uint64_t seq = 3;
  for (const Keep& k : kept) {
    const auto replayed = live.session.replay(k.topic, encode(k.payload), at(5100));
    REQUIRE(replayed.has_value());
    CHECK(replayed->topic == k.topic);
    CHECK(replayed->payload.seq == seq++);
    CHECK(replayed->payload.timestamp == static_cast<std::uint64_t>(kUnixStart + 5100));
    for (const Metric& m : replayed->payload.metrics) {
      CHECK(m.name.empty());
      CHECK(m.alias.has_value());
      CHECK(m.is_historical);
      CHECK(m.timestamp == static_cast<std::uint64_t>(k.time_unix_ms));
    }
  }
  CHECK(find_alias(live.session.replay(kept[0].topic, encode(kept[0].payload), at(5200))->payload,
                   257)
            ->value == Value{2.0});
}

TEST_CASE("while waiting for the primary host, data is kept too") {
  auto o = options();
  o.primary_host_id = "scada";
  auto session = make_session(o);
  (void)session.begin_connect(at(0));
  (void)session.on_connected(at(0));
  const DeviceSample samples[] = {boom(1.0)};
  const auto actions = session.update(samples, at(100));
  CHECK(topics(actions) == std::vector<std::string>{"keep spBv1.0/plant/DDATA/gw1/boom"});
}

TEST_CASE("a replay is refused when not live, for an unknown or offline device, and for what is not a kept DDATA") {
  LiveSession live;
  live.session.on_connection_lost();
  const auto kept = keep_outage(live.session);
  const auto bytes = encode(kept[0].payload);
  CHECK(live.session.replay(kept[0].topic, bytes, at(4000)).error() == ReplayRefusal::not_live);
  (void)live.session.begin_connect(at(5000));
  (void)live.session.on_connected(at(5000));
  CHECK(live.session.replay("spBv1.0/plant/DDATA/gw1/crane", bytes, at(5100)).error() ==
        ReplayRefusal::unknown_device);
  CHECK(live.session.replay("spBv1.0/plant/NDATA/gw1", bytes, at(5100)).error() ==
        ReplayRefusal::malformed);
  CHECK(live.session.replay(kept[0].topic, std::vector<std::uint8_t>{0xFF}, at(5100)).error() ==
        ReplayRefusal::malformed);
  const Payload unknown_names{
      1, std::nullopt, {Metric{"angle_z", {}, 1, DataType::Double, true, 1.0, {}}}};
  CHECK(live.session.replay(kept[0].topic, encode(unknown_names), at(5100)).error() ==
        ReplayRefusal::malformed);
  const DeviceSample gone[] = {offline(boom(1.0))};
  (void)live.session.update(gone, at(5200));
  CHECK(live.session.replay(kept[0].topic, bytes, at(5300)).error() ==
        ReplayRefusal::device_offline);
}
