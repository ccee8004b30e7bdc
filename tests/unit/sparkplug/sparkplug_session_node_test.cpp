// The edge node's own metrics, the system clock (sparkplug/edge_node_session.h update_node):
// in the NBIRTH, and in NDATA when they change, by alias, in seq with the devices' messages.
#include <doctest/doctest.h>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

const NodeSample kSynchronised{true, 12.5};
const NodeSample kUnsynchronised{false, std::nullopt};

}  // namespace

TEST_CASE("NBIRTH carries the clock: Clock/synchronised (Boolean) and Clock/error_ms (Double), with aliases") {
  auto session = make_session();
  (void)session.update_node(kSynchronised, at(0));
  (void)session.begin_connect(at(0));
  const Payload nbirth = publishes(session.on_connected(at(0))).at(0).payload;
  const Metric* synchronised = find_metric(nbirth, "Clock/synchronised");
  REQUIRE(synchronised != nullptr);
  CHECK(synchronised->datatype == DataType::Boolean);
  CHECK(synchronised->value == Value{true});
  CHECK(synchronised->alias == 3u);
  const Metric* error = find_metric(nbirth, "Clock/error_ms");
  REQUIRE(error != nullptr);
  CHECK(error->datatype == DataType::Double);
  CHECK(error->value == Value{12.5});
  CHECK(error->alias == 4u);
}

TEST_CASE("an unsynchronised clock is Clock/synchronised false and Clock/error_ms null in the NBIRTH") {
  LiveSession live;  // never told: what the node knows of a clock nobody read
  const Payload nbirth = publishes(live.connected).at(0).payload;
  CHECK(find_metric(nbirth, "Clock/synchronised")->value == Value{false});
  CHECK(find_metric(nbirth, "Clock/error_ms")->value == Value{});
}

TEST_CASE("tck-id-topics-ndata-seq-num, -mqtt: the clock lost is an NDATA by alias at once, next in seq") {
  LiveSession live;
  (void)live.session.update_node(kSynchronised, at(50));  // synchronised since the birth
  const auto actions = live.session.update_node(kUnsynchronised, at(100));
  REQUIRE(topics(actions) == std::vector<std::string>{"spBv1.0/plant/NDATA/gw1"});
  const Publish ndata = publishes(actions).at(0);
  CHECK(ndata.qos == 0);
  CHECK_FALSE(ndata.retain);
  CHECK(ndata.payload.seq == 4u);  // NBIRTH 0, two DBIRTHs, the first NDATA 3
  CHECK(ndata.payload.timestamp == static_cast<std::uint64_t>(kUnixStart + 100));
  REQUIRE(ndata.payload.metrics.size() == 2);
  for (const Metric& m : ndata.payload.metrics) CHECK(m.name.empty());
  CHECK(find_alias(ndata.payload, kClockSynchronisedAlias)->value == Value{false});
  CHECK(find_alias(ndata.payload, kClockErrorAlias)->value == Value{});
  // Nothing changed: nothing sent.
  CHECK(live.session.update_node(kUnsynchronised, at(200)).empty());
}

TEST_CASE("tck-id-topics-ndata-payload: the clock's bound drifting is sent at most every max_interval, with what changed") {
  LiveSession live;  // max_interval 10 s
  (void)live.session.update_node(kSynchronised, at(0));
  CHECK(live.session.update_node(NodeSample{true, 13.0}, at(1000)).empty());
  CHECK(live.session.update_node(NodeSample{true, 17.5}, at(9999)).empty());
  const auto due = publishes(live.session.update_node(NodeSample{true, 17.5}, at(10000)));
  REQUIRE(due.size() == 1);
  REQUIRE(due[0].payload.metrics.size() == 1);
  CHECK(due[0].payload.metrics[0].alias == kClockErrorAlias);
  CHECK(due[0].payload.metrics[0].value == Value{17.5});
  // The same value again after another interval: no change, nothing to report.
  CHECK(live.session.update_node(NodeSample{true, 17.5}, at(20000)).empty());
}

TEST_CASE("the clock changing while not connected sends nothing, the next NBIRTH has it") {
  auto session = make_session();
  CHECK(session.update_node(kSynchronised, at(0)).empty());
  (void)session.begin_connect(at(0));
  CHECK(session.update_node(kUnsynchronised, at(10)).empty());  // connecting: no NDATA
  const Payload nbirth = publishes(session.on_connected(at(20))).at(0).payload;
  CHECK(find_metric(nbirth, "Clock/synchronised")->value == Value{false});
  CHECK(session.update_node(kUnsynchronised, at(30)).empty());  // as born
}
