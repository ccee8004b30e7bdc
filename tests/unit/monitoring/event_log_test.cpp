// The event record (monitoring/event_log.h, event_record.h): numbered, kept on disk across a
// reopen, filtered newest first, handed on after a number, and its JSON both ways.
#include <doctest/doctest.h>

#include <cmath>

#include "monitoring/event_log.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::monitoring;

namespace {

EventRecord alarm_at(std::int64_t unix_ms, std::string sensor, std::string state) {
  EventRecord e;
  e.unix_ms = unix_ms;
  e.sensor = std::move(sensor);
  e.kind = "alarm";
  e.alarm = "x_high";
  e.level = "warning";
  e.state = std::move(state);
  e.value = 2.31;
  e.threshold = 2.0;
  return e;
}

}  // namespace

TEST_CASE("event log: numbered, kept across a reopen, newest first, filtered") {
  test::ScratchDir scratch("tiltgate-events");
  const std::filesystem::path dir = scratch.path("events");
  {
    EventLog log(dir);
    CHECK(log.append(alarm_at(1000, "mast", "set")).seq == 1);
    CHECK(log.append(alarm_at(2000, "pier", "set")).seq == 2);
    EventRecord offline;
    offline.unix_ms = 3000;
    offline.sensor = "mast";
    offline.kind = "offline";
    offline.text = "the sensor stopped answering";
    CHECK(log.append(offline).seq == 3);
    log.sync();
  }
  EventLog reopened(dir);
  CHECK(reopened.last_seq() == 3);
  CHECK(reopened.append(alarm_at(4000, "mast", "clear")).seq == 4);  // the numbers go on
  const auto all = reopened.recent({});
  REQUIRE(all.size() == 4);
  CHECK(all[0].seq == 4);
  CHECK(all[3].seq == 1);
  CHECK(all[3] == [] { auto e = alarm_at(1000, "mast", "set"); e.seq = 1; return e; }());
  EventQuery mast;
  mast.sensor = "mast";
  mast.kind = "alarm";
  CHECK(reopened.recent(mast).size() == 2);
  EventQuery window;
  window.since = 2000;
  window.until = 4000;
  const auto between = reopened.recent(window);
  REQUIRE(between.size() == 2);
  CHECK(between[0].unix_ms == 3000);
  EventQuery one;
  one.limit = 1;
  CHECK(reopened.recent(one).size() == 1);
  const auto after = reopened.after(2, 10);
  REQUIRE(after.size() == 2);
  CHECK(after[0].seq == 3);  // oldest first
  CHECK(reopened.after(4, 10).empty());
}

TEST_CASE("event log: without a directory it keeps the events in memory and says so") {
  EventLog log(std::filesystem::path{});
  CHECK(log.append(alarm_at(1, "mast", "set")).seq == 1);
  CHECK(log.recent({}).size() == 1);
  REQUIRE(log.fault().has_value());
}

TEST_CASE("event JSON: an alarm's record as the issue gives it, and read back") {
  EventRecord e = alarm_at(1796638502250, "mast", "set");
  e.seq = 7;
  const std::string text = event_json(e);
  CHECK(text ==
        R"({"seq":7,"time":"2026-12-07T10:15:02.250Z","unix_ms":1796638502250,"sensor":"mast",)"
        R"("kind":"alarm","alarm":"x_high","level":"warning","state":"set","value":2.31,)"
        R"("threshold":2})");
  CHECK(event_from_json(text) == e);
  EventRecord b;
  b.seq = 8;
  b.unix_ms = 5;
  b.sensor = "mast";
  b.kind = "baseline";
  b.x = 0.25;
  b.y = 0;
  b.previous_x = 0;
  b.previous_y = 0;
  b.by = "console admin";
  CHECK(event_json(b).find(R"("value":{"x":0.25,"y":0},"previous":{"x":0,"y":0},"by":"console admin")") !=
        std::string::npos);
  CHECK(event_from_json(event_json(b)) == b);
  CHECK_FALSE(event_from_json("not json").has_value());
  CHECK_FALSE(event_from_json(R"({"seq":-1})").has_value());
}
