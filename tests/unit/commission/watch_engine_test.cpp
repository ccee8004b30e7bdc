// `watch` as the engine runs it (commission/watch_engine.h) on a simulated bus: a reading event
// per sensor and poll, and a round event per round with every sensor's reading and note.
#include <doctest/doctest.h>

#include "commission/watch_engine.h"
#include "unit/commission/support/engine_bench.h"

namespace tiltgate {
namespace {

using test::EngineBench;
using test::simulated_h6;

TEST_CASE("watch reports each sensor's reading in every round, and stops after --count rounds") {
  EngineBench bench({simulated_h6(223), simulated_h6(7, 12.5, 0)}, {223, 7});
  const WatchOptions options{2, 10};
  const int exit_code =
      bench.run(watch_sensors(*bench.bus, options, bench.report, bench.stopping));
  CHECK(exit_code == 0);
  const auto rounds = bench.all<WatchRoundEvent>();
  REQUIRE(rounds.size() == 2);
  CHECK(rounds[0].round == 1);
  CHECK(rounds[1].round == 2);
  for (const WatchRoundEvent& round : rounds) {
    REQUIRE(round.readings.size() == 2);
    CHECK(round.readings[0].address == 223);
    CHECK(round.readings[1].address == 7);
    CHECK(round.readings[0].result == PollResult::reading);
    REQUIRE(round.readings[1].angle_x.has_value());
    CHECK(*round.readings[1].angle_x == doctest::Approx(12.5));
    // No --model: each sensor's note is the model found, nothing about its readings.
    CHECK(round.notes == std::vector<std::string>{"address 223: model h6 (detected)",
                                                  "address 7: model h6 (detected)"});
  }
  // Each poll was reported as it came, before its round.
  const auto readings = bench.all<SensorReadingEvent>();
  CHECK(readings.size() == 4);
  REQUIRE(bench.events.size() == 6);
  CHECK(std::holds_alternative<SensorReadingEvent>(bench.events[0]));
  CHECK(std::holds_alternative<SensorReadingEvent>(bench.events[1]));
  CHECK(std::holds_alternative<WatchRoundEvent>(bench.events[2]));
  // A second reading gives a rate.
  CHECK(rounds[1].readings[0].readings_per_second.has_value());
}

TEST_CASE("watch shows a silent sensor as no reply in its reading, with no note") {
  EngineBench bench({simulated_h6(223)}, {224});
  const int exit_code =
      bench.run(watch_sensors(*bench.bus, WatchOptions{1, 10}, bench.report, bench.stopping));
  CHECK(exit_code == 0);
  const auto rounds = bench.all<WatchRoundEvent>();
  REQUIRE(rounds.size() == 1);
  REQUIRE(rounds[0].readings.size() == 1);
  CHECK(rounds[0].readings[0].result == PollResult::silent);
  CHECK(rounds[0].notes == std::vector<std::string>{""});
}

TEST_CASE("watch's options are checked as the command line checks them, each error naming its option") {
  CHECK(watch_option_errors(WatchOptions{0, 500}).empty());
  CHECK(watch_option_errors(WatchOptions{1, 10}).empty());
  CHECK(watch_option_errors(WatchOptions{100'000'000, 3'600'000}).empty());
  CHECK(watch_option_errors(WatchOptions{-1, 500}) ==
        UsageErrors{"--count: -1 is not in 1..100000000 (0: until stopped)"});
  CHECK(watch_option_errors(WatchOptions{2, 9}) ==
        UsageErrors{"--interval: 9 is not in 10..3600000 ms"});
  CHECK(watch_option_errors(WatchOptions{-1, 3'600'001}).size() == 2);
}

}  // namespace
}  // namespace tiltgate
