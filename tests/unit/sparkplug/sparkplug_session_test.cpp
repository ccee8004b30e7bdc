// The edge node's session establishment and births (sparkplug/edge_node_session.h), named
// after the Sparkplug 3.0.0 normative statements they check.
#include <doctest/doctest.h>

#include <set>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

TEST_CASE("tck-id-payloads-ndeath-will-message-qos, -retain, tck-id-topics-ndeath-payload: the will is NDEATH with bdSeq only") {
  auto session = make_session();
  const Will will = session.begin_connect(at(0));
  CHECK(will.topic == "spBv1.0/plant/NDEATH/gw1");
  CHECK(will.qos == 1);
  CHECK_FALSE(will.retain);
  CHECK_FALSE(will.payload.seq.has_value());  // tck-id-topics-ndeath-seq
  REQUIRE(will.payload.metrics.size() == 1);
  const Metric& bd_seq = will.payload.metrics[0];
  CHECK(bd_seq.name == "bdSeq");
  // tck-id-message-flow-edge-node-birth-publish-will-message-payload-bdSeq: Int64
  CHECK(bd_seq.datatype == DataType::Int64);
  CHECK(bd_seq.value == Value{std::int64_t{0}});
  CHECK(session.state() == SessionState::connecting);
}

TEST_CASE("tck-id-topics-nbirth-bdseq-increment: bdSeq starts at 0, goes up by one on every CONNECT sent, 255 then 0") {
  auto first = make_session();
  CHECK(first.begin_connect(at(0)).bd_seq == 0);
  first.connect_sent();
  CHECK(first.begin_connect(at(1)).bd_seq == 1);  // a CONNECT that failed still used its bdSeq
  first.connect_sent();
  CHECK(first.bd_seq() == 1);
  // Attempts whose TCP connect was refused sent no CONNECT: the next one uses the same bdSeq.
  CHECK(first.begin_connect(at(2)).bd_seq == 2);
  CHECK(first.begin_connect(at(3)).bd_seq == 2);
  CHECK(first.begin_connect(at(4)).bd_seq == 2);
  first.connect_sent();
  CHECK(first.begin_connect(at(5)).bd_seq == 3);
  // After a restart, from the bdSeq the caller stored.
  auto restarted = make_session(options(), 41);
  CHECK(restarted.begin_connect(at(0)).bd_seq == 42);
  auto wrapped = make_session(options(), 255);
  const Will will = wrapped.begin_connect(at(0));
  CHECK(will.bd_seq == 0);
  CHECK(will.payload.metrics[0].value == Value{std::int64_t{0}});
}

TEST_CASE("tck-id-message-flow-edge-node-ncmd-subscribe, -device-dcmd-subscribe: NCMD and DCMD at QoS 1 before any birth") {
  LiveSession live;
  const auto order = topics(live.connected);
  REQUIRE(order.size() >= 3);
  CHECK(order[0] == "subscribe spBv1.0/plant/NCMD/gw1");
  CHECK(order[1] == "subscribe spBv1.0/plant/DCMD/gw1/+");
  CHECK(order[2] == "spBv1.0/plant/NBIRTH/gw1");
  for (const auto& s : all_of<Subscribe>(live.connected)) CHECK(s.qos == 1);
}

TEST_CASE("tck-id-payloads-nbirth-seq: NBIRTH has seq 0, QoS 0, not retained (tck-id-topics-nbirth-mqtt)") {
  LiveSession live;
  const Publish nbirth = publishes(live.connected).at(0);
  CHECK(nbirth.topic == "spBv1.0/plant/NBIRTH/gw1");
  CHECK(nbirth.payload.seq == 0u);
  CHECK(nbirth.qos == 0);
  CHECK_FALSE(nbirth.retain);
  CHECK(nbirth.payload.timestamp ==
        static_cast<std::uint64_t>(kUnixStart));  // tck-id-payloads-nbirth-timestamp
  CHECK(live.session.state() == SessionState::live);
}

TEST_CASE("tck-id-topics-nbirth-bdseq-matching: NBIRTH's bdSeq is the will's, as an Int64") {
  auto session = make_session(options(), 6);
  const Will will = session.begin_connect(at(0));
  const Publish nbirth = publishes(session.on_connected(at(0))).at(0);
  const Metric* bd_seq = find_metric(nbirth.payload, "bdSeq");
  REQUIRE(bd_seq != nullptr);
  CHECK(bd_seq->datatype == DataType::Int64);
  CHECK(bd_seq->value == will.payload.metrics[0].value);
  CHECK(bd_seq->value == Value{std::int64_t{7}});
}

TEST_CASE("tck-id-payloads-nbirth-rebirth-req: NBIRTH has Node Control/Rebirth, Boolean false, without an alias") {
  LiveSession live;
  const Payload nbirth = publishes(live.connected).at(0).payload;
  const Metric* rebirth = find_metric(nbirth, "Node Control/Rebirth");
  REQUIRE(rebirth != nullptr);
  CHECK(rebirth->datatype ==
        DataType::Boolean);  // tck-id-operational-behavior-data-commands-rebirth-datatype
  CHECK(rebirth->value == Value{false});
  // tck-id-operational-behavior-data-commands-rebirth-name-aliases
  CHECK_FALSE(rebirth->alias.has_value());
}

TEST_CASE("NBIRTH carries the node's version and its number of buses") {
  LiveSession live;
  const Payload nbirth = publishes(live.connected).at(0).payload;
  CHECK(find_metric(nbirth, "Properties/version")->value == Value{std::string("0.1.0")});
  CHECK(find_metric(nbirth, "Properties/buses")->value == Value{std::uint32_t{2}});
  CHECK(find_metric(nbirth, "Properties/buses")->datatype == DataType::UInt32);
}

TEST_CASE("tck-id-payloads-dbirth-order: a DBIRTH for every online sensor right after the NBIRTH") {
  LiveSession live;
  CHECK(topics(live.connected) ==
        std::vector<std::string>{"subscribe spBv1.0/plant/NCMD/gw1",
                                 "subscribe spBv1.0/plant/DCMD/gw1/+", "spBv1.0/plant/NBIRTH/gw1",
                                 "spBv1.0/plant/DBIRTH/gw1/boom", "spBv1.0/plant/DBIRTH/gw1/mast"});
  const auto births = publishes(live.connected);
  // tck-id-topics-dbirth-seq: one more than the message before.
  CHECK(births[1].payload.seq == 1u);
  CHECK(births[2].payload.seq == 2u);
  CHECK(births[1].qos == 0);  // tck-id-topics-dbirth-mqtt
  CHECK_FALSE(births[1].retain);
}

TEST_CASE("tck-id-topics-dbirth-metrics, tck-id-payloads-alias-birth-requirement: every metric with name, alias, datatype, value") {
  LiveSession live;
  const Payload dbirth = publishes(live.connected).at(1).payload;
  std::vector<std::string> names;
  for (const Metric& m : dbirth.metrics) {
    names.push_back(m.name);
    CHECK(m.alias.has_value());
    CHECK(m.datatype != DataType::Unknown);  // tck-id-payloads-metric-datatype-req
  }
  CHECK(names == std::vector<std::string>{"angle_x", "angle_y", "tilt", "relative_x", "relative_y",
                                          "status", "online", "stale", "wrong_device", "alarms",
                                          "alarms_danger", "alarms_latched", "age_ms",
                                          "Properties/model",
                                          "Properties/serial", "Properties/firmware",
                                          "Settings/filter", "Settings/zero_x"});
  CHECK(find_metric(dbirth, "angle_x")->value == Value{1.0});
  CHECK(find_metric(dbirth, "angle_x")->datatype == DataType::Double);
  CHECK(find_metric(dbirth, "online")->value == Value{true});
  CHECK(find_metric(dbirth, "alarms")->datatype == DataType::UInt16);
  CHECK(find_metric(dbirth, "age_ms")->value == Value{std::int64_t{3}});
  CHECK(find_metric(dbirth, "Settings/filter")->value == Value{4.0});
  // tck-id-operational-behavior-data-publish-dbirth-values: a value not known is null.
  CHECK(find_metric(dbirth, "Settings/zero_x")->value == Value{});
}

TEST_CASE("a single-axis sensor's DBIRTH has no angle_y") {
  LiveSession live;
  const Payload dbirth = publishes(live.connected).at(2).payload;
  CHECK(find_metric(dbirth, "angle_y") == nullptr);
  CHECK(find_metric(dbirth, "angle_x")->value == Value{3.0});
  CHECK(find_metric(dbirth, "Properties/serial")->value == Value{});  // not reported yet
}

TEST_CASE("DBIRTH angles carry the engineering unit deg, identity is Properties/model, serial, firmware") {
  LiveSession live;
  const Payload dbirth = publishes(live.connected).at(1).payload;
  for (const char* angle : {"angle_x", "angle_y", "tilt"}) {
    CAPTURE(angle);
    const Metric* m = find_metric(dbirth, angle);
    REQUIRE(m->properties.size() == 1);
    CHECK(m->properties[0] == Property{"engUnit", DataType::String, std::string("deg")});
  }
  CHECK(find_metric(dbirth, "status")->properties.empty());
  CHECK(find_metric(dbirth, "Properties/model")->value == Value{std::string("h6")});
  CHECK(find_metric(dbirth, "Properties/serial")->value == Value{std::string("9600223")});
  CHECK(find_metric(dbirth, "Properties/firmware")->value == Value{std::string("Rev A.8")});
}

TEST_CASE("tck-id-payloads-alias-uniqueness: no two metrics of the node share an alias") {
  LiveSession live;
  std::set<std::uint64_t> aliases;
  std::size_t with_alias = 0;
  for (const Publish& p : publishes(live.connected)) {
    for (const Metric& m : p.payload.metrics) {
      if (!m.alias) continue;
      ++with_alias;
      aliases.insert(*m.alias);
    }
  }
  CHECK(aliases.size() == with_alias);
  CHECK(with_alias == 4 + 18 + 14);  // the node's version, buses and clock; boom's; mast's
  // 256 × (position + 1) + the metric's number: the same in every session.
  CHECK(find_metric(publishes(live.connected).at(1).payload, "angle_x")->alias == 257u);
  CHECK(find_metric(publishes(live.connected).at(2).payload, "angle_x")->alias == 513u);
}

TEST_CASE("tck-id-payloads-name-birth-data-requirement: metrics carry the reading's time, the payload the publishing time") {
  auto session = make_session();
  const DeviceSample samples[] = {boom(1.0, 0.0, -250)};  // read 250 ms before the CONNACK
  (void)session.update(samples, at(0));
  (void)session.begin_connect(at(0));
  const Publish dbirth = publishes(session.on_connected(at(0))).at(1);
  CHECK(dbirth.payload.timestamp == static_cast<std::uint64_t>(kUnixStart));
  for (const Metric& m : dbirth.payload.metrics) {
    CHECK(m.timestamp == static_cast<std::uint64_t>(kUnixStart - 250));
  }
}

TEST_CASE("tck-id-payloads-sequence-num-incrementing: every later message has seq + 1, and 255 is followed by 0") {
  LiveSession live;
  std::uint64_t expected = 3;  // NBIRTH 0, DBIRTH boom 1, DBIRTH mast 2
  for (int i = 1; i <= 600; ++i) {
    const DeviceSample samples[] = {boom(i % 2 == 0 ? 1.0 : 5.0, 0.0, i * 200)};
    for (const Publish& p : publishes(live.session.update(samples, at(i * 200)))) {
      CHECK(p.payload.seq == expected);
      expected = (expected + 1) % 256;
    }
  }
  CHECK(expected == (3 + 600) % 256);
}

TEST_CASE("tck-id-operational-behavior-edge-node-intentional-disconnect-ndeath: a clean stop publishes NDEATH, then disconnects") {
  LiveSession live;
  const auto actions = live.session.stop(at(500));
  CHECK(topics(actions) == std::vector<std::string>{"spBv1.0/plant/NDEATH/gw1", "disconnect"});
  const Publish ndeath = publishes(actions).at(0);
  CHECK_FALSE(ndeath.payload.seq.has_value());
  CHECK(ndeath.payload.metrics.at(0).value == Value{std::int64_t{0}});  // this connection's bdSeq
  CHECK(live.session.state() == SessionState::disconnected);
  CHECK(live.session.stop(at(600)).empty());  // stopped: nothing more
}

TEST_CASE("tck-id-operational-behavior-data-commands-rebirth-action-1..3: Rebirth=true births again, same bdSeq, same connection") {
  LiveSession live;
  const DeviceSample samples[] = {boom(5.0, 0.0, 200)};
  (void)live.session.update(samples, at(200));  // DDATA seq 3
  Metric rebirth;
  rebirth.name = "Node Control/Rebirth";
  rebirth.datatype = DataType::Boolean;
  rebirth.value = true;
  const auto actions =
      live.session.on_message("spBv1.0/plant/NCMD/gw1", command({rebirth}), at(300));
  CHECK(topics(actions) == std::vector<std::string>{"spBv1.0/plant/NBIRTH/gw1",
                                                    "spBv1.0/plant/DBIRTH/gw1/boom",
                                                    "spBv1.0/plant/DBIRTH/gw1/mast"});
  const auto births = publishes(actions);
  CHECK(births[0].payload.seq == 0u);
  CHECK(births[1].payload.seq == 1u);
  CHECK(find_metric(births[0].payload, "bdSeq")->value == Value{std::int64_t{0}});
  CHECK(find_metric(births[1].payload, "angle_x")->value == Value{5.0});  // the latest sample
  CHECK(live.session.commands().rebirth == 1);
  CHECK(live.session.state() == SessionState::live);
}

TEST_CASE("a session is refused for an invalid id, a repeated device, or intervals out of order") {
  auto o = options();
  o.group_id = "plant/north";
  CHECK(EdgeNodeSession::create(o, {"boom"}, std::nullopt).error().find("group_id") == 0);
  o = options();
  o.edge_node_id = "";
  CHECK_FALSE(EdgeNodeSession::create(o, {"boom"}, std::nullopt).has_value());
  o = options();
  o.primary_host_id = "host#1";
  CHECK_FALSE(EdgeNodeSession::create(o, {"boom"}, std::nullopt).has_value());
  CHECK(EdgeNodeSession::create(options(), {"boom", "boom"}, std::nullopt).error() ==
        "the device id \"boom\" repeats");
  CHECK_FALSE(EdgeNodeSession::create(options(), {"boom+"}, std::nullopt).has_value());
  o = options();
  o.min_interval = 2000ms;
  o.max_interval = 1000ms;
  CHECK_FALSE(EdgeNodeSession::create(o, {"boom"}, std::nullopt).has_value());
  o = options();
  o.on_change_deg = -1;
  CHECK_FALSE(EdgeNodeSession::create(o, {"boom"}, std::nullopt).has_value());
}
