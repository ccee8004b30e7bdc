// A sensor's samples summed up per interval for the long record (monitoring/interval_summary.h):
// least, mean and greatest per channel, intervals aligned to UTC, channels without values, the
// owner's timer closing a silent sensor's interval, and a clock stepped back never reordering
// what comes out.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "monitoring/interval_summary.h"

using namespace tiltgate::monitoring;
using namespace std::chrono_literals;

namespace {

constexpr std::int64_t k1201 = 1796644860000;  // 2026-12-07T12:01:00.000Z
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Sample at(std::int64_t unix_ms, double x, double y = kNaN, double tilt = kNaN,
          double temperature = kNaN, bool synchronised = true) {
  Sample s;
  s.unix_ms = unix_ms;
  s.x = x;
  s.y = y;
  s.tilt = tilt;
  s.temperature = temperature;
  s.clock_synchronised = synchronised;
  return s;
}

}  // namespace

TEST_CASE("an interval's least, mean and greatest per channel, given out when a sample of the next arrives") {
  IntervalSummary summary(60s);
  CHECK_FALSE(summary.add(at(k1201 + 0, 1.0, -2.0, 2.0, 20.0)).has_value());
  CHECK_FALSE(summary.add(at(k1201 + 20'000, 3.0, -1.0, 3.0, 21.0)).has_value());
  CHECK_FALSE(summary.add(at(k1201 + 59'999, 2.0, -3.0, 4.0, 22.5)).has_value());
  CHECK(summary.open_start() == k1201);
  const auto closed = summary.add(at(k1201 + 60'000, 9.0));
  REQUIRE(closed.has_value());
  CHECK(closed->start_unix_ms == k1201);
  CHECK(closed->length_ms == 60'000);
  CHECK(closed->end_unix_ms() == k1201 + 60'000);
  CHECK(closed->samples == 3);
  CHECK(closed->unsynchronised == 0);
  CHECK(closed->x.min == 1.0f);
  CHECK(closed->x.mean == 2.0f);
  CHECK(closed->x.max == 3.0f);
  CHECK(closed->y.min == -3.0f);
  CHECK(closed->y.mean == -2.0f);
  CHECK(closed->y.max == -1.0f);
  CHECK(closed->tilt.mean == 3.0f);
  CHECK(closed->temperature.min == 20.0f);
  CHECK(closed->temperature.mean == doctest::Approx(21.1666667f));
  CHECK(closed->temperature.max == 22.5f);
  CHECK(summary.open_start() == k1201 + 60'000);  // the sample that closed it opened the next
}

TEST_CASE("intervals are aligned to UTC multiples of their length, whenever the first sample comes") {
  IntervalSummary minute(60s);
  minute.add(at(k1201 + 37'123, 1.0));
  CHECK(minute.open_start() == k1201);
  const auto closed = minute.add(at(k1201 + 60'000 + 1, 2.0));
  REQUIRE(closed.has_value());
  CHECK(closed->start_unix_ms == k1201);  // 12:01:00.000, not 12:01:37.123
  CHECK(minute.open_start() == k1201 + 60'000);

  IntervalSummary ten(10s);
  ten.add(at(k1201 + 9'999, 1.0));
  CHECK(ten.open_start() == k1201);
  CHECK(ten.add(at(k1201 + 10'000, 1.0)).has_value());  // 12:01:10.000 starts the next

  CHECK(interval_start(k1201 + 59'999, 60'000) == k1201);
  CHECK(interval_start(k1201 + 60'000, 60'000) == k1201 + 60'000);
  CHECK(interval_start(-1, 60'000) == -60'000);  // before 1970: floor, not toward zero
  CHECK(interval_start(-60'000, 60'000) == -60'000);
}

TEST_CASE("a channel with no value in an interval is NaN, and every sample is counted whatever it carries") {
  IntervalSummary summary(60s);
  summary.add(at(k1201, 1.5, kNaN, 1.5));  // a single-axis sensor without temperature
  summary.add(at(k1201 + 1'000, kNaN));     // no fresh reading: counted, no values
  summary.add(at(k1201 + 2'000, 2.5, kNaN, std::numeric_limits<double>::infinity()));
  const auto closed = summary.close_now();
  REQUIRE(closed.has_value());
  CHECK(closed->samples == 3);
  CHECK(closed->x.min == 1.5f);
  CHECK(closed->x.mean == 2.0f);  // of the two values, not of three samples
  CHECK(closed->x.max == 2.5f);
  CHECK(std::isnan(closed->y.min));
  CHECK(std::isnan(closed->y.mean));
  CHECK(std::isnan(closed->y.max));
  CHECK(closed->tilt.min == 1.5f);  // infinity is not a value
  CHECK(closed->tilt.max == 1.5f);
  CHECK(std::isnan(closed->temperature.mean));
}

TEST_CASE("close_due closes a silent sensor's interval once its end has come, and not before") {
  IntervalSummary summary(60s);
  CHECK_FALSE(summary.close_due(k1201).has_value());  // nothing open
  summary.add(at(k1201 + 5'000, 1.0));
  CHECK_FALSE(summary.close_due(k1201 + 59'999).has_value());
  const auto closed = summary.close_due(k1201 + 60'000);
  REQUIRE(closed.has_value());
  CHECK(closed->start_unix_ms == k1201);
  CHECK(closed->samples == 1);
  CHECK_FALSE(summary.open_start().has_value());
  CHECK_FALSE(summary.close_due(k1201 + 600'000).has_value());  // no empty intervals after it
  // A late sample of the interval just closed would write it twice: dropped.
  CHECK_FALSE(summary.add(at(k1201 + 59'000, 1.0)).has_value());
  CHECK(summary.dropped_behind() == 1);
  CHECK_FALSE(summary.open_start().has_value());
}

TEST_CASE("a sensor silent for a while: its next sample closes the open interval only, no empty ones between") {
  IntervalSummary summary(60s);
  summary.add(at(k1201, 1.0));
  const auto closed = summary.add(at(k1201 + 3'600'000, 2.0));  // an hour later
  REQUIRE(closed.has_value());
  CHECK(closed->start_unix_ms == k1201);
  CHECK(summary.open_start() == k1201 + 3'600'000);
}

TEST_CASE("a clock stepped back: a sample older than the open interval is dropped and counted, and what comes out stays in order") {
  IntervalSummary summary(60s);
  summary.add(at(k1201 + 10'000, 1.0));
  summary.add(at(k1201 + 70'000, 2.0));  // 12:02:10: closes 12:01
  // The clock steps back 30 s: 12:01:50 is before the open 12:02 interval.
  CHECK_FALSE(summary.add(at(k1201 + 50'000, 100.0)).has_value());
  CHECK(summary.dropped_behind() == 1);
  CHECK(summary.open_start() == k1201 + 60'000);
  // A sample within the open interval, though earlier than the last one, is that interval's.
  summary.add(at(k1201 + 61'000, 4.0));
  const auto closed = summary.add(at(k1201 + 120'000, 5.0));
  REQUIRE(closed.has_value());
  CHECK(closed->start_unix_ms == k1201 + 60'000);
  CHECK(closed->samples == 2);
  CHECK(closed->x.max == 4.0f);  // the dropped 100.0 is in no interval
  // close_due with the clock behind the open interval's end leaves it open.
  CHECK_FALSE(summary.close_due(k1201 + 100'000).has_value());
  CHECK(summary.open_start() == k1201 + 120'000);
}

TEST_CASE("after a restart, samples before where the record already ends are dropped, counted") {
  // The record on disk ends at 12:03:00 (LongRecord::written_until()); the clock came back at
  // 12:02.
  IntervalSummary summary(60s, k1201 + 120'000);
  CHECK_FALSE(summary.add(at(k1201 + 65'000, 1.0)).has_value());
  CHECK_FALSE(summary.add(at(k1201 + 119'999, 1.0)).has_value());
  CHECK(summary.dropped_behind() == 2);
  CHECK_FALSE(summary.open_start().has_value());
  summary.add(at(k1201 + 120'000, 1.0));
  CHECK(summary.open_start() == k1201 + 120'000);
  // A longer interval that would straddle the record's end is dropped too: they would overlap.
  IntervalSummary longer(300s, k1201 + 120'000);  // its interval 12:00..12:05
  CHECK_FALSE(longer.add(at(k1201 + 150'000, 1.0)).has_value());
  CHECK(longer.dropped_behind() == 1);
  longer.add(at(k1201 + 240'000, 1.0));  // 12:05
  CHECK(longer.open_start() == k1201 + 240'000);
}

TEST_CASE("samples taken while the clock was not synchronised are counted per interval") {
  IntervalSummary summary(60s);
  summary.add(at(k1201, 1.0, kNaN, kNaN, kNaN, false));
  summary.add(at(k1201 + 1'000, 1.0, kNaN, kNaN, kNaN, true));
  summary.add(at(k1201 + 2'000, 1.0, kNaN, kNaN, kNaN, false));
  const auto first = summary.add(at(k1201 + 60'000, 1.0, kNaN, kNaN, kNaN, true));
  REQUIRE(first.has_value());
  CHECK(first->samples == 3);
  CHECK(first->unsynchronised == 2);
  const auto second = summary.close_now();
  REQUIRE(second.has_value());
  CHECK(second->unsynchronised == 0);  // counted afresh each interval
  Sample unsaid;
  unsaid.unix_ms = k1201 + 200'000;
  summary.add(unsaid);
  CHECK(summary.close_now()->unsynchronised == 1);  // a sample that does not say is not trusted
}

TEST_CASE("close_now gives the open interval at a stop, and the rest of that interval is not given again") {
  IntervalSummary summary(60s);
  summary.add(at(k1201 + 1'000, 1.0));
  const auto closed = summary.close_now();
  REQUIRE(closed.has_value());
  CHECK(closed->samples == 1);
  CHECK_FALSE(summary.close_now().has_value());
  CHECK_FALSE(summary.add(at(k1201 + 2'000, 1.0)).has_value());
  CHECK(summary.dropped_behind() == 1);
  CHECK(summary.interval() == 60s);
}
