// What each value source reads from a sensor's view (mapping/source_values.h): every source a
// map file may name gives a number from a sensor with a reading, except the text and written
// values, and each counter and state value reads its own field.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "mapping/source_values.h"
#include "mapping/value_source.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using S = ValueSource;

namespace {

// Every field a source reads set to a value of its own.
SensorState full_state(SteadyClock::time_point now) {
  SensorState s;
  s.online = true;
  s.identity_known = true;
  Reading r;
  r.angle_x = 1.5;
  r.angle_y = -2.5;
  r.raw_counts = 1234;
  r.raw_temperature = 25;
  r.temperature_c = 21.5;
  r.taken = now - 10ms;
  s.reading = r;
  s.counters.transactions = 7;
  s.counters.polls_ok = 5;
  s.counters.polls_failed = 6;
  s.counters.timeouts = 8;
  s.counters.checksum_errors = 9;
  s.counters.io_errors = 10;
  s.counters.late_replies = 11;
  s.counters.last_refusal = 4;
  s.reply_timeout = 120ms;
  s.protection_level = 2;
  s.bus_address = 12;
  s.sample_seq = 13;
  return s;
}

bool has_no_number(S source) {
  return source == S::serial || source == S::firmware || source == S::written ||
         source == S::setting;
}

}  // namespace

TEST_CASE("every source a map file may name reads a number from a sensor with a reading") {
  const auto now = SteadyClock::now();
  const SensorState state = full_state(now);
  SensorView view{state, now, 1000ms, {}};
  view.model_code = 14;
  // Processed with a baseline and a lever (line_scheduling/sensor_processing.h), as the gateway
  // does every reading: the relative angles and the displacement are derived.
  DerivedState derived;
  derived.angle_x = 1.0;
  derived.angle_y = -2.0;
  derived.tilt = 2.2;
  derived.relative_x = 0.5;
  derived.relative_y = -0.25;
  derived.displacement_x_mm = 8.7;
  derived.displacement_y_mm = -4.4;
  derived.displacement_mm = 9.75;
  derived.valid = true;
  view.derived = &derived;
  for (const auto& named : source_names()) {
    CAPTURE(std::string(named.name));
    if (has_no_number(named.value))
      CHECK(std::isnan(source_value(named.value, view)));
    else
      CHECK_FALSE(std::isnan(source_value(named.value, view)));
  }
}

TEST_CASE("each counter and state source reads its own field") {
  const auto now = SteadyClock::now();
  const SensorState state = full_state(now);
  SensorView view{state, now, 1000ms, {}};
  view.model_code = 14;
  CHECK(source_value(S::angle_x, view) == 1.5);
  CHECK(source_value(S::angle_y, view) == -2.5);
  CHECK(source_value(S::angle_x_cdeg, view) == 150);
  CHECK(source_value(S::angle_y_cdeg, view) == -250);
  CHECK(source_value(S::raw_counts, view) == 1234);
  CHECK(source_value(S::raw_temperature, view) == 25);
  CHECK(source_value(S::temperature, view) == 21.5);
  CHECK(source_value(S::online, view) == 1);
  CHECK(source_value(S::stale, view) == 0);
  CHECK(source_value(S::age_ms, view) == 10);
  CHECK(source_value(S::transactions, view) == 7);
  CHECK(source_value(S::polls_ok, view) == 5);
  CHECK(source_value(S::polls_failed, view) == 6);
  CHECK(source_value(S::timeouts, view) == 8);
  CHECK(source_value(S::checksum_errors, view) == 9);
  CHECK(source_value(S::io_errors, view) == 10);
  CHECK(source_value(S::late_replies, view) == 11);
  CHECK(source_value(S::last_nak, view) == 4);
  CHECK(source_value(S::reply_timeout_ms, view) == 120);
  CHECK(source_value(S::lock_level, view) == 2);
  CHECK(source_value(S::bus_address, view) == 12);
  CHECK(source_value(S::sample_seq, view) == 13);
  CHECK(source_value(S::model_code, view) == 14);
}

TEST_CASE("a sensor without a reading: no angle, no raw value, and 65535 for what it never said") {
  const auto now = SteadyClock::now();
  const SensorState state;
  const SensorView view{state, now, 1000ms, {}};
  CHECK(std::isnan(source_value(S::angle_x, view)));
  CHECK(std::isnan(source_value(S::tilt, view)));
  CHECK(std::isnan(source_value(S::raw_counts, view)));
  CHECK(std::isnan(source_value(S::temperature, view)));
  CHECK(source_value(S::last_nak, view) == 65535);
  CHECK(source_value(S::lock_level, view) == 65535);
  CHECK(source_value(S::age_ms, view) == 65535);
}
