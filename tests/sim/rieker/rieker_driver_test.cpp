// The Rieker driver over a real SerialLine on a pseudo-terminal, against the simulator.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cmath>

#include "rieker/rieker_driver.h"
#include "rieker/simulator.h"
#include "serial/serial_line.h"
#include "sim/support/driver_bench.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;
using namespace tiltgate::rieker;
using namespace std::chrono_literals;
using test::run_coroutine;

namespace {

// One Rieker bus (8N1 at the factory 125000 baud) with these sensors.
struct Bench : test::DriverBench<RiekerSimulator> {
  explicit Bench(std::vector<SimulatedSensorOptions> sensors, int retries = 1)
      : DriverBench(simulator_options(std::move(sensors)), line_options(retries)) {}

  static RiekerSimulatorOptions simulator_options(std::vector<SimulatedSensorOptions> sensors) {
    RiekerSimulatorOptions options;
    options.sensors = std::move(sensors);
    return options;
  }
  static SerialLineOptions line_options(int retries) {
    SerialLineOptions options;
    options.name = "line1";
    options.retries = retries;
    return options;
  }
};

SimulatedSensorOptions h6(std::uint16_t address, double x = 1.5, double y = -2.25) {
  SimulatedSensorOptions s;
  s.model = Model::h6;
  s.address = address;
  s.serial = "962285";
  s.angle_x = x;
  s.angle_y = y;
  return s;
}

SimulatedSensorOptions h4360(std::uint16_t address, double x = 12.5) {
  SimulatedSensorOptions s = h6(address, x, 0);
  s.model = Model::h4360;
  s.serial = "123456";
  return s;
}

RiekerDriverOptions driver_for(std::uint16_t address, Model model = Model::h6) {
  RiekerDriverOptions options;
  options.model = model;
  options.address = address;
  options.busy_wait = 5ms;
  options.reply_timeouts = test::kBenchReplyTimeouts;
  return options;
}

}  // namespace

TEST_CASE("a first poll reads the identity, then both angles of an H6") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  bench.poll(driver);
  const SensorState& s = driver.state();
  CHECK(s.online);
  CHECK(s.identity_known);
  CHECK(s.serial == "962285");
  CHECK(s.firmware == "Rev A.8");
  CHECK(s.protection_level == std::optional<std::uint16_t>(0));
  REQUIRE(s.reading.has_value());
  CHECK(s.reading->angle_x == 1.5);
  CHECK(s.reading->angle_y == -2.25);
  CHECK(s.sample_seq == 1);
  CHECK(s.counters.polls_ok == 1);
  CHECK(s.counters.transactions == 4);  // serial, firmware, lock level, angles
  bench.poll(driver);
  CHECK(s.counters.transactions == 5);  // identity is not read again
  CHECK(s.sample_seq == 2);
}

TEST_CASE("an H4360 is read with the single-axis type code and has no Y angle") {
  Bench bench({h4360(101)});
  RiekerDriver driver(driver_for(101, Model::h4360));
  bench.poll(driver);
  REQUIRE(driver.state().reading.has_value());
  CHECK(driver.state().reading->angle_x == 12.5);
  CHECK(std::isnan(driver.state().reading->angle_y));
}

TEST_CASE("NAK 2 when a dual-axis type code is sent to an H4360") {
  Bench bench({h4360(101)});
  RiekerDriver driver(driver_for(101, Model::h6));  // misconfigured model
  bench.poll(driver);
  CHECK(driver.state().online);  // it answers, so it is there
  CHECK_FALSE(driver.state().reading.has_value());
  CHECK(driver.state().counters.polls_failed == 1);
  CHECK(driver.state().counters.refusals[2] == 1);
  CHECK(driver.state().counters.last_refusal == std::optional<std::uint8_t>(2));
}

TEST_CASE("acknowledged settings are published, but not a refused one or a zeroed offset") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  const KnownSettings& settings = driver.state().settings;
  CHECK(settings.get(WriteTarget::bus_address) == 223);  // known from the start
  CHECK_FALSE(settings.get(WriteTarget::filter).has_value());  // the protocol reads none back
  CHECK(bench.write(driver, WriteTarget::filter, 2).has_value());
  CHECK(bench.write(driver, WriteTarget::zero_x, 0.5).has_value());
  CHECK(settings.get(WriteTarget::filter) == 2);
  CHECK(settings.get(WriteTarget::zero_x) == 0.5);
  bench.sim->sensor(0).faults().busy = 1000;
  CHECK_FALSE(bench.write(driver, WriteTarget::filter, 5).has_value());
  bench.sim->sensor(0).faults().busy = 0;
  CHECK(settings.get(WriteTarget::filter) == 2);
  CHECK(bench.write(driver, WriteTarget::command, 1).has_value());  // zero here
  CHECK_FALSE(settings.get(WriteTarget::zero_x).has_value());  // no longer 0.5, value unknown
  CHECK(bench.write(driver, WriteTarget::bus_address, 300).has_value());
  CHECK(settings.get(WriteTarget::bus_address) == 300);
}

TEST_CASE("every setting is written with the lock dance and the sensor ends locked") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  SimulatedSensor& sensor = bench.sim->sensor(0);

  CHECK(bench.write(driver, WriteTarget::filter, 2).has_value());
  CHECK(sensor.filter() == 2);
  CHECK(sensor.lock_level() == LockLevel::locked);
  CHECK(driver.state().protection_level == std::optional<std::uint16_t>(0));

  CHECK(bench.write(driver, WriteTarget::zero_x, 0.5).has_value());
  CHECK(sensor.zero_offset(Axis::x) == 0.5);
  CHECK(bench.write(driver, WriteTarget::zero_y, -1.25).has_value());
  CHECK(sensor.zero_offset(Axis::y) == -1.25);
  bench.poll(driver);
  CHECK(driver.state().reading->angle_x == 1.0);   // 1.5 - 0.5
  CHECK(driver.state().reading->angle_y == -1.0);  // -2.25 + 1.25

  CHECK(bench.write(driver, WriteTarget::command, 1).has_value());  // zero here, temporary
  bench.poll(driver);
  CHECK(driver.state().reading->angle_x == doctest::Approx(0.0));
  CHECK(bench.write(driver, WriteTarget::command, 2).has_value());  // permanent
  CHECK(sensor.zero_offset(Axis::x) == doctest::Approx(1.5));

  CHECK(bench.write(driver, WriteTarget::baud_code, 8).has_value());
  CHECK(sensor.pending_baud_code() == std::optional<int>(8));

  CHECK(bench.write(driver, WriteTarget::command, 3).has_value());  // restart
  CHECK(sensor.restarts() == 1);
  CHECK(sensor.baud_code() == 8);
  CHECK_FALSE(driver.state().identity_known);  // read again after a restart
  bench.poll(driver);
  CHECK(driver.state().identity_known);
  CHECK_FALSE(driver.state().last_write_failed);
}

TEST_CASE("set address: the driver follows the sensor to its new address") {
  Bench bench({h6(101)});
  RiekerDriver driver(driver_for(101));
  CHECK(bench.write(driver, WriteTarget::bus_address, 223).has_value());
  CHECK(bench.sim->sensor_by_address(223) != nullptr);
  CHECK(driver.address() == 223);
  CHECK(driver.state().bus_address == 223);
  bench.poll(driver);
  CHECK(driver.state().counters.polls_ok == 1);
  CHECK(bench.sim->sensor(0).lock_level() == LockLevel::locked);
}

TEST_CASE("values a Rieker sensor cannot take are refused before anything is sent") {
  RiekerDriver h6_driver(driver_for(223));
  CHECK(h6_driver.check_write(WriteTarget::filter, 7).error().kind == WriteErrorKind::bad_value);
  CHECK(h6_driver.check_write(WriteTarget::filter, 2.5).error().kind == WriteErrorKind::bad_value);
  CHECK(h6_driver.check_write(WriteTarget::baud_code, 0).error().kind == WriteErrorKind::bad_value);
  CHECK(h6_driver.check_write(WriteTarget::bus_address, 0).error().kind == WriteErrorKind::bad_value);
  CHECK(h6_driver.check_write(WriteTarget::zero_x, NAN).error().kind == WriteErrorKind::bad_value);
  CHECK(h6_driver.check_write(spectron::setting::eeprom_value, 1).error().kind ==
        WriteErrorKind::not_supported);
  RiekerDriver h4360_driver(driver_for(101, Model::h4360));
  CHECK(h4360_driver.check_write(WriteTarget::zero_y, 0).error().kind ==
        WriteErrorKind::not_supported);
}

TEST_CASE("NAK 5 busy is retried, and reported as busy when it lasts") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  bench.sim->sensor(0).faults().busy = 2;
  CHECK(bench.write(driver, WriteTarget::filter, 3).has_value());
  CHECK(driver.state().counters.refusals[5] == 2);
  bench.sim->sensor(0).faults().busy = 100;
  auto result = bench.write(driver, WriteTarget::filter, 5);
  REQUIRE_FALSE(result.has_value());
  CHECK(result.error().kind == WriteErrorKind::busy);
  CHECK(driver.state().last_write_failed);
}

TEST_CASE("every NAK code maps to the documented write error") {
  const auto kind_for = [](std::uint8_t code) {
    return to_write_error(ExchangeError{ExchangeError::Kind::nak, LineError::timeout, code, ""}, "x").kind;
  };
  CHECK(kind_for(0) == WriteErrorKind::refused);
  CHECK(kind_for(1) == WriteErrorKind::refused);
  CHECK(kind_for(2) == WriteErrorKind::refused);
  CHECK(kind_for(3) == WriteErrorKind::rejected);
  CHECK(kind_for(4) == WriteErrorKind::refused);
  CHECK(kind_for(5) == WriteErrorKind::busy);
  CHECK(to_write_error(ExchangeError{ExchangeError::Kind::line, LineError::timeout, 0, ""}, "x").kind ==
        WriteErrorKind::no_response);
}

TEST_CASE("a silent sensor times out, goes offline, and comes back") {
  Bench bench({h6(223)}, /*retries=*/1);
  RiekerDriver driver(driver_for(223));
  bench.poll(driver);
  REQUIRE(driver.state().online);
  bench.sim->sensor(0).faults().silent = 2;  // both attempts of the next exchange
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
  CHECK(driver.state().counters.polls_failed == 1);
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE("a corrupted reply is counted and the retry succeeds") {
  Bench bench({h6(223)}, /*retries=*/2);
  RiekerDriver driver(driver_for(223));
  bench.poll(driver);
  bench.sim->sensor(0).faults().corrupt_crc = 1;
  bench.poll(driver);
  CHECK(driver.state().counters.checksum_errors == 1);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE("garbage before a reply on the line does not lose the reply") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  bench.sim->sensor(0).faults().garbage = 3;
  bench.poll(driver);
  CHECK(driver.state().identity_known);
  CHECK(driver.state().counters.polls_ok == 1);
  CHECK(driver.state().counters.timeouts == 0);
}

TEST_CASE("a sensor on another address is silent to this driver") {
  Bench bench({h6(224)}, /*retries=*/0);
  RiekerDriver driver(driver_for(223));
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
}

TEST_CASE("an unplugged adapter fails polls, and after the replug identity is read again") {
  Bench bench({h6(223)});
  RiekerDriver driver(driver_for(223));
  bench.poll(driver);
  REQUIRE(driver.state().identity_known);
  const auto generation = bench.line->generation();

  bench.sim->unplug();
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.io_errors >= 1);

  REQUIRE(bench.sim->replug().has_value());
  REQUIRE(bench.wait_for_reopen(generation));
  const auto transactions = driver.state().counters.transactions;
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().identity_known);
  CHECK(driver.state().counters.transactions == transactions + 4);  // identity again + angles
}
