// `info` as the engine runs it (commission/info_engine.h) on a simulated bus: what it reports of
// each sensor, as events, and its exit code.
#include <doctest/doctest.h>

#include "commission/info_engine.h"
#include "unit/commission/support/engine_bench.h"

namespace tiltgate {
namespace {

using test::EngineBench;
using test::simulated_h6;

TEST_CASE("info reports an answering sensor's identity and angles as one reading event") {
  EngineBench bench({simulated_h6(223)}, {223});
  const int exit_code = bench.run(
      show_info(*bench.bus, registered_family_commands(), bench.report, bench.stopping));
  CHECK(exit_code == 0);
  const auto readings = bench.all<SensorReadingEvent>();
  REQUIRE(readings.size() == 1);
  const SensorReadingEvent& reading = readings.front();
  CHECK(reading.address == 223);
  CHECK(reading.model == "h6");
  CHECK(reading.serial == "962285");
  CHECK(reading.firmware == "Rev A.8");
  CHECK(reading.lock_level.has_value());
  CHECK(reading.result == PollResult::reading);
  CHECK(reading.status == "ok");
  REQUIRE(reading.angle_x.has_value());
  CHECK(*reading.angle_x == doctest::Approx(1.5));
  REQUIRE(reading.angle_y.has_value());
  CHECK(*reading.angle_y == doctest::Approx(-2.25));
  CHECK(bench.all<FailedEvent>().empty());
}

TEST_CASE("info reports a silent sensor as no reply and a failure naming its address, and goes on") {
  EngineBench bench({simulated_h6(223)}, {224, 223});
  const int exit_code = bench.run(
      show_info(*bench.bus, registered_family_commands(), bench.report, bench.stopping));
  CHECK(exit_code == 1);
  const auto readings = bench.all<SensorReadingEvent>();
  REQUIRE(readings.size() == 2);
  CHECK(readings[0].address == 224);
  CHECK(readings[0].result == PollResult::silent);
  CHECK(readings[0].status == "no reply");
  CHECK(readings[1].address == 223);
  CHECK(readings[1].result == PollResult::reading);
  const auto failures = bench.all<FailedEvent>();
  REQUIRE(failures.size() == 1);
  CHECK(failures[0].exit_code == 1);
  CHECK(failures[0].message.find("no reply from address 224") != std::string::npos);
  // The failure follows the silent sensor's reading, before anything of the next sensor.
  REQUIRE(bench.events.size() >= 3);
  CHECK(std::holds_alternative<SensorReadingEvent>(bench.events[0]));
  CHECK(std::holds_alternative<FailedEvent>(bench.events[1]));
}

}  // namespace
}  // namespace tiltgate
