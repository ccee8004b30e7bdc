// Commands and the primary host (sparkplug/edge_node_session.h): DCMD writes with commands on
// and off, NCMD other than a rebirth, malformed payloads, and births gated on the host's STATE.
#include <doctest/doctest.h>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

constexpr std::string_view kBoomCommands = "spBv1.0/plant/DCMD/gw1/boom";
constexpr std::uint64_t kBoomFilter = 256 + 32, kBoomZeroX = 256 + 33, kBoomX = 257;

Metric by_alias(std::uint64_t alias, Value value) {
  Metric m;
  m.alias = alias;
  m.value = std::move(value);
  return m;
}

Metric by_name(std::string name, Value value) {
  Metric m;
  m.name = std::move(name);
  m.value = std::move(value);
  return m;
}

EdgeNodeOptions with_commands() {
  auto o = options();
  o.commands = true;
  return o;
}

EdgeNodeOptions with_primary_host() {
  auto o = options();
  o.primary_host_id = "scada";
  return o;
}

std::vector<std::uint8_t> state(bool online, std::uint64_t timestamp) {
  const std::string json = std::string("{\"online\":") + (online ? "true" : "false") +
                           ",\"timestamp\":" + std::to_string(timestamp) + "}";
  return {json.begin(), json.end()};
}

}  // namespace

TEST_CASE("commands = false: every DCMD is ignored and counted") {
  LiveSession live;
  const auto actions =
      live.session.on_message(kBoomCommands, command({by_alias(kBoomFilter, 2.0)}), at(100));
  CHECK(actions.empty());
  CHECK(live.session.commands().ignored == 1);
  CHECK(live.session.commands().write == 0);
  (void)live.session.on_message(kBoomCommands, std::vector<std::uint8_t>{0xFF}, at(100));
  CHECK(live.session.commands().ignored == 2);  // not even looked at
}

TEST_CASE("commands = true: a DCMD of a writable setting by alias is a write for the caller") {
  LiveSession live(with_commands());
  const auto actions = live.session.on_message(
      kBoomCommands,
      command({by_alias(kBoomFilter, std::uint32_t{2}), by_alias(kBoomZeroX, -0.25)}), at(100));
  const auto writes = all_of<Write>(actions);
  REQUIRE(writes.size() == 2);
  CHECK(writes[0].device == "boom");
  CHECK(writes[0].setting == "filter");
  CHECK(writes[0].value == 2.0);
  CHECK(writes[1].setting == "zero_x");
  CHECK(writes[1].value == -0.25);
  CHECK(publishes(actions).empty());  // the result shows in a later DDATA, from the sample
  CHECK(live.session.commands().write == 2);
}

TEST_CASE("a DCMD naming the setting instead of its alias is a write too") {
  LiveSession live(with_commands());
  const auto writes = all_of<Write>(
      live.session.on_message(kBoomCommands, command({by_name("Settings/filter", 8.0)}), at(100)));
  REQUIRE(writes.size() == 1);
  CHECK(writes[0].setting == "filter");
}

TEST_CASE("a DCMD of a metric that is not a setting, a text value or an unknown alias is refused and counted") {
  LiveSession live(with_commands());
  const auto actions = live.session.on_message(
      kBoomCommands,
      command({by_alias(kBoomX, 1.0), by_alias(kBoomFilter, std::string("2")), by_alias(9999, 1.0),
               by_alias(kBoomFilter, Value{})}),
      at(100));
  CHECK(actions.empty());
  CHECK(live.session.commands().refused == 4);
}

TEST_CASE("a DCMD for a device not born (offline, or not ours) is refused") {
  LiveSession live(with_commands());
  const DeviceSample gone[] = {offline(boom(1.0))};
  (void)live.session.update(gone, at(200));
  CHECK(live.session.on_message(kBoomCommands, command({by_alias(kBoomFilter, 1.0)}), at(300))
            .empty());
  CHECK(live.session
            .on_message("spBv1.0/plant/DCMD/gw1/crane", command({by_alias(kBoomFilter, 1.0)}),
                        at(300))
            .empty());
  CHECK(live.session.commands().refused == 2);
}

TEST_CASE("malformed payloads and topics are counted, never fatal") {
  LiveSession live(with_commands());
  const std::vector<std::uint8_t> garbage = {0x12, 0x7F, 0x00};
  CHECK(live.session.on_message(kBoomCommands, garbage, at(100)).empty());
  CHECK(live.session.on_message("spBv1.0/plant/NCMD/gw1", garbage, at(100)).empty());
  CHECK(live.session.on_message("spBv1.0/plant/NCMD", garbage, at(100)).empty());
  CHECK(live.session.commands().malformed == 3);
  CHECK(live.session.state() == SessionState::live);
  // Commands for another edge node are not ours: not counted at all.
  CHECK(live.session.on_message("spBv1.0/plant/NCMD/gw2", garbage, at(100)).empty());
  CHECK(live.session.commands().malformed == 3);
}

TEST_CASE("tck-id-operational-behavior-data-commands-ncmd-rebirth-value: an NCMD other than Rebirth = true is refused") {
  LiveSession live;
  const auto actions = live.session.on_message(
      "spBv1.0/plant/NCMD/gw1",
      command({by_name("Node Control/Rebirth", false), by_name("Node Control/Reboot", true)}),
      at(100));
  CHECK(actions.empty());
  CHECK(live.session.commands().refused == 2);
  CHECK(live.session.commands().rebirth == 0);
}

TEST_CASE("tck-id-message-flow-edge-node-birth-publish-phid-wait: with a primary host, births only once its STATE is online") {
  auto session = make_session(with_primary_host());
  const DeviceSample samples[] = {boom(1.0)};
  (void)session.update(samples, at(0));
  (void)session.begin_connect(at(0));
  const auto connected = session.on_connected(at(0));
  CHECK(topics(connected) == std::vector<std::string>{"subscribe spBv1.0/plant/NCMD/gw1",
                                                      "subscribe spBv1.0/plant/DCMD/gw1/+",
                                                      "subscribe spBv1.0/STATE/scada"});
  CHECK(session.state() == SessionState::waiting_for_host);
  // The retained STATE of a host that is offline: still waiting.
  CHECK(session.on_message("spBv1.0/STATE/scada", state(false, 100), at(10)).empty());
  CHECK(session.state() == SessionState::waiting_for_host);
  // tck-id-message-flow-edge-node-birth-publish-phid-wait-id: another host's STATE is not it.
  CHECK(session.on_message("spBv1.0/STATE/other", state(true, 200), at(20)).empty());
  const auto online = session.on_message("spBv1.0/STATE/scada", state(true, 200), at(30));
  CHECK(topics(online) ==
        std::vector<std::string>{"spBv1.0/plant/NBIRTH/gw1", "spBv1.0/plant/DBIRTH/gw1/boom"});
  CHECK(session.state() == SessionState::live);
}

TEST_CASE("tck-id-message-flow-edge-node-birth-publish-phid-offline: the host going offline means NDEATH and a reconnect") {
  auto session = make_session(with_primary_host());
  (void)session.begin_connect(at(0));
  session.connect_sent();
  (void)session.on_connected(at(0));
  (void)session.on_message("spBv1.0/STATE/scada", state(true, 200), at(10));
  const auto offline_state = session.on_message("spBv1.0/STATE/scada", state(false, 300), at(20));
  CHECK(topics(offline_state) ==
        std::vector<std::string>{"spBv1.0/plant/NDEATH/gw1", "disconnect"});
  CHECK(publishes(offline_state).at(0).payload.metrics.at(0).value == Value{std::int64_t{0}});
  CHECK(session.state() == SessionState::disconnected);
  // Later: a new connection, the next bdSeq, and births again once the host is back.
  CHECK(session.begin_connect(at(5000)).bd_seq == 1);
  (void)session.on_connected(at(5000));
  CHECK(session.state() == SessionState::waiting_for_host);
  CHECK(topics(session.on_message("spBv1.0/STATE/scada", state(true, 5000), at(5010))).size() == 1);
}

TEST_CASE("tck-id-message-flow-edge-node-birth-publish-phid-wait-timestamp: a STATE older than the last is ignored") {
  auto session = make_session(with_primary_host());
  (void)session.begin_connect(at(0));
  (void)session.on_connected(at(0));
  (void)session.on_message("spBv1.0/STATE/scada", state(true, 500), at(10));
  CHECK(session.on_message("spBv1.0/STATE/scada", state(false, 400), at(20)).empty());
  CHECK(session.state() == SessionState::live);
}

TEST_CASE("a STATE that is not the host's JSON is counted as malformed and changes nothing") {
  auto session = make_session(with_primary_host());
  (void)session.begin_connect(at(0));
  (void)session.on_connected(at(0));
  const std::string old_style = "ONLINE";  // Sparkplug 2.2
  CHECK(session
            .on_message("spBv1.0/STATE/scada",
                        std::vector<std::uint8_t>(old_style.begin(), old_style.end()), at(10))
            .empty());
  CHECK(session.commands().malformed == 1);
  CHECK(session.state() == SessionState::waiting_for_host);
}

TEST_CASE("a rebirth request before the births (the host not online yet) is ignored") {
  auto session = make_session(with_primary_host());
  (void)session.begin_connect(at(0));
  (void)session.on_connected(at(0));
  CHECK(session
            .on_message("spBv1.0/plant/NCMD/gw1", command({by_name("Node Control/Rebirth", true)}),
                        at(10))
            .empty());
  CHECK(session.commands().ignored == 1);
}
