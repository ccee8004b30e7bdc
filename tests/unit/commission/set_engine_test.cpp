// `set` as the engine runs it (commission/set_engine.h) on a simulated bus: each write's answer,
// the move, the sensor read back, as events; and nothing sent when the request cannot be made.
#include <doctest/doctest.h>

#include "commission/set_engine.h"
#include "unit/commission/support/engine_bench.h"

namespace tiltgate {
namespace {

using test::EngineBench;
using test::simulated_h6;

int set_on(EngineBench& bench, std::vector<std::string> words) {
  const SetRequest request{SetArguments{std::move(words), false}, ""};
  return bench.run(set_sensor(*bench.bus, request, registered_family_commands(), bench.report,
                              bench.stopping));
}

TEST_CASE("set reports the sensor's ack of the setting, then the value it reads back") {
  EngineBench bench({simulated_h6(223)}, {223});
  CHECK(set_on(bench, {"filter", "2"}) == 0);
  const auto answers = bench.all<SettingAcknowledgedEvent>();
  REQUIRE(answers.size() == 1);
  CHECK(answers[0].address == 223);
  CHECK(answers[0].setting.find("filter") != std::string::npos);
  CHECK(answers[0].value == 2);
  CHECK(answers[0].result == "ack");
  CHECK_FALSE(answers[0].refusal_code.has_value());
  const auto applied = bench.all<SettingAppliedEvent>();
  REQUIRE(applied.size() == 1);
  CHECK(applied[0].setting == "filter 2");
  CHECK(applied[0].address == 223);
  const auto readings = bench.all<SensorReadingEvent>();
  REQUIRE(readings.size() == 1);
  CHECK(readings[0].result == PollResult::reading);
  CHECK(readings[0].serial == "962285");
  const auto read = bench.all<SettingsReadEvent>();
  REQUIRE(read.size() == 1);
  REQUIRE(read[0].settings.size() == 1);
  CHECK(read[0].settings[0].value == std::optional<double>(2));
  CHECK(bench.all<FailedEvent>().empty());
  CHECK(bench.sim->sensor(0).filter() == 2);
}

TEST_CASE("set reports a NAK as the sensor's answer with its code, and fails") {
  EngineBench bench({simulated_h6(223)}, {223});
  bench.sim->sensor(0).faults().by_function[rieker::Function::set_filter].nak = 100;
  CHECK(set_on(bench, {"filter", "2"}) == 1);
  const auto answers = bench.all<SettingAcknowledgedEvent>();
  REQUIRE(answers.size() == 1);
  CHECK(answers[0].result == "nak");
  CHECK(answers[0].refusal_code.has_value());
  const auto failures = bench.all<FailedEvent>();
  REQUIRE(failures.size() == 1);
  CHECK(failures[0].exit_code == 1);
  CHECK(failures[0].message.find("at address 223: the sensor refused") != std::string::npos);
  CHECK(bench.all<SettingAppliedEvent>().empty());
}

TEST_CASE("set address reports the move, and reads the sensor back at its new address") {
  EngineBench bench({simulated_h6(223)}, {223});
  CHECK(set_on(bench, {"address", "7"}) == 0);
  const auto moves = bench.all<AddressMovedEvent>();
  REQUIRE(moves.size() == 1);
  CHECK(moves[0].from == 223);
  CHECK(moves[0].to == 7);
  CHECK(moves[0].gateway_sensor.empty());  // no gateway owns the bus
  const auto readings = bench.all<SensorReadingEvent>();
  REQUIRE(readings.size() == 1);
  CHECK(readings[0].address == 7);
  CHECK(readings[0].result == PollResult::reading);
}

TEST_CASE("set sends nothing to a silent sensor, and says so") {
  EngineBench bench({simulated_h6(223)}, {224});
  CHECK(set_on(bench, {"filter", "2"}) == 1);
  CHECK(bench.all<SettingAcknowledgedEvent>().empty());
  const auto failures = bench.all<FailedEvent>();
  REQUIRE(failures.size() == 1);
  CHECK(failures[0].message.find("no reply from address 224") != std::string::npos);
  CHECK(failures[0].message.find("nothing was sent") != std::string::npos);
}

TEST_CASE("set refuses a value out of the setting's range before the bus is used") {
  EngineBench bench({simulated_h6(223)}, {223});
  CHECK(set_on(bench, {"filter", "9"}) == 2);
  REQUIRE(bench.events.size() == 1);
  const auto* failed = std::get_if<FailedEvent>(&bench.events[0]);
  REQUIRE(failed != nullptr);
  CHECK(failed->exit_code == 2);
  CHECK(failed->message.find("nothing was sent") != std::string::npos);
  CHECK(bench.sim->counters().requests_seen == 0);
}

}  // namespace
}  // namespace tiltgate
