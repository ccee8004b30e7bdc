// What each 08 count and 11 say of a sensor's exchanges (gateway/unit_diagnostics.h).
#include <doctest/doctest.h>

#include "gateway/unit_diagnostics.h"

using namespace tiltgate;

namespace {

SensorCounters exchanges() {
  SensorCounters c;
  c.requests = 40;      // 30 answered, 4 garbled, 6 silent
  c.replies = 30;
  c.garbled = 4;
  c.no_reply = 6;
  c.checksum_errors = 3;  // three of the garbled ones failed their CRC, one its length
  c.late_replies = 2;
  c.refused = 5;        // 2 of them busy
  c.busy = 2;
  c.overruns = 7;
  return c;
}

}  // namespace

TEST_CASE("each count of 08 from the sensor's exchanges") {
  const SensorCounters c = exchanges();
  CHECK(diagnostic_count(c, 0x000B) == 40 + 30 + 4 + 2);  // requests and every reply heard
  CHECK(diagnostic_count(c, 0x000C) == 4);  // the garbled ones, CRC or framing
  CHECK(diagnostic_count(c, 0x000D) == 5);
  CHECK(diagnostic_count(c, 0x000E) == 40);
  CHECK(diagnostic_count(c, 0x000F) == 6);
  CHECK(diagnostic_count(c, 0x0010) == 3);
  CHECK(diagnostic_count(c, 0x0011) == 2);
  CHECK(diagnostic_count(c, 0x0012) == 7);
  CHECK_FALSE(diagnostic_count(c, 0x0000).has_value());
  CHECK_FALSE(diagnostic_count(c, 0x000A).has_value());
  CHECK_FALSE(diagnostic_count(c, 0x0013).has_value());
}

TEST_CASE("a checksum error before a valid reply in one attempt still counts as a bus error") {
  SensorCounters c;
  c.checksum_errors = 2;  // noise frames skipped, the reply then taken
  CHECK(diagnostic_count(c, 0x000C) == 2);
}

TEST_CASE("counts are 16 bits and wrap, as Modbus counters do") {
  SensorCounters c;
  c.requests = 65536 + 5;
  CHECK(diagnostic_count(c, 0x000E) == 5);
  c.replies = 70000;
  CHECK(comm_event_counter(c).events == 70000 - 65536);
  CHECK(comm_event_counter(c).status == 0x0000);
}

TEST_CASE("an aggregate's counts are its sensors' summed") {
  SensorCounters total;
  add_counts(total, exchanges());
  add_counts(total, exchanges());
  CHECK(diagnostic_count(total, 0x000E) == 80);
  CHECK(diagnostic_count(total, 0x0011) == 4);
  CHECK(diagnostic_count(total, 0x0010) == 6);
  CHECK(comm_event_counter(total).events == 60);
}
