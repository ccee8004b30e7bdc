// The Rieker lock dance when one step fails, and sensors that answer after the reply time-out:
// a late reply is never taken as the answer to a later request (ACKs all look alike), and a
// sensor that is always late gets a longer time-out instead of flapping online/offline.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "rieker/rieker_driver.h"
#include "rieker/simulator.h"
#include "serial/serial_line.h"
#include "sim/support/driver_bench.h"

using namespace tiltgate;
using namespace tiltgate::rieker;
using namespace std::chrono_literals;

namespace {

constexpr std::uint16_t kAddress = 223;

// One H6 on a Rieker bus; `adjust` sets the line's time-out, guard and retries.
struct Bench : test::DriverBench<RiekerSimulator> {
  explicit Bench(const std::function<void(SerialLineOptions&)>& adjust = {})
      : DriverBench(simulator_options(), SerialLineOptions{}, adjust) {}

  static RiekerSimulatorOptions simulator_options() {
    SimulatedSensorOptions h6;
    h6.model = Model::h6;
    h6.address = kAddress;
    RiekerSimulatorOptions options;
    options.sensors = {h6};
    return options;
  }
  SimulatedSensor& sensor() { return sim->sensor(0); }
  // Lets replies still on their way arrive and be flushed before the next case.
  void drain(std::chrono::milliseconds how_long) { test::run_for(io, how_long); }
};

RiekerDriverOptions driver_options(ReplyTimeouts timeouts = test::kBenchReplyTimeouts) {
  RiekerDriverOptions options;
  options.name = "boom";
  options.model = Model::h6;
  options.address = kAddress;
  options.busy_wait = 5ms;
  options.reply_timeouts = timeouts;
  return options;
}

FunctionFaults& faults_of(Bench& bench, Function function) {
  return bench.sensor().faults().by_function[function];
}

}  // namespace

TEST_CASE("Set Filter's own NAK 3 is a rejected write, and the sensor is locked again") {
  Bench bench;
  RiekerDriver driver(driver_options());
  faults_of(bench, Function::set_filter).nak = 1;
  const auto result = bench.write(driver, WriteTarget::filter, 2);
  REQUIRE_FALSE(result.has_value());
  CHECK(result.error().kind == WriteErrorKind::rejected);
  CHECK(bench.sensor().filter() == kDefaultFilter);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 2);  // unlock, lock
  CHECK(bench.sensor().lock_level() == LockLevel::locked);
  CHECK(driver.state().last_write_failed);
}

// A sensor that stops answering mid-write is not kept waiting for: the write is answered
// without the re-lock, which the next poll that reaches the sensor sends before it measures.
TEST_CASE("Set Filter's own time-out is a write with no response, and the next poll locks the sensor again") {
  Bench bench([](SerialLineOptions& o) { o.retries = 1; });
  RiekerDriver driver(driver_options());
  faults_of(bench, Function::set_filter).silent = 2;  // both attempts
  const auto result = bench.write(driver, WriteTarget::filter, 2);
  REQUIRE_FALSE(result.has_value());
  CHECK(result.error().kind == WriteErrorKind::no_response);
  CHECK(bench.sensor().filter() == kDefaultFilter);
  CHECK(bench.sensor().requests_of(Function::set_filter) == 2);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 1);  // the unlock
  CHECK(bench.sensor().lock_level() == LockLevel::unlocked);
  bench.poll(driver);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 2);
  CHECK(bench.sensor().lock_level() == LockLevel::locked);
  CHECK(driver.state().counters.polls_ok == 1);
}

TEST_CASE("a NAKed unlock fails the write, sends no setting, and still sends the re-lock") {
  Bench bench;
  RiekerDriver driver(driver_options());
  faults_of(bench, Function::change_lock).nak = 1;  // the unlock only
  const auto result = bench.write(driver, WriteTarget::filter, 2);
  REQUIRE_FALSE(result.has_value());
  CHECK(result.error().kind == WriteErrorKind::rejected);
  CHECK(result.error().detail.rfind("unlock", 0) == 0);
  CHECK(bench.sensor().requests_of(Function::set_filter) == 0);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 2);  // unlock, re-lock
  CHECK(bench.sensor().lock_level() == LockLevel::locked);
}

TEST_CASE("an unlock that times out fails the write at once, and the next poll that reaches the sensor locks it") {
  Bench bench([](SerialLineOptions& o) { o.retries = 1; });
  RiekerDriver driver(driver_options());
  faults_of(bench, Function::change_lock).silent = 2;  // both attempts of the unlock
  const auto result = bench.write(driver, WriteTarget::filter, 2);
  REQUIRE_FALSE(result.has_value());
  CHECK(result.error().kind == WriteErrorKind::no_response);
  CHECK(bench.sensor().requests_of(Function::set_filter) == 0);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 2);  // the 2 unlock attempts
  // Its ACK may have been lost: the next poll locks it first, in case.
  bench.poll(driver);
  CHECK(bench.sensor().requests_of(Function::change_lock) == 3);
  CHECK(bench.sensor().lock_level() == LockLevel::locked);
  CHECK(driver.state().counters.polls_ok == 1);
}

// The sweep: a sensor that answers everything N ms late, for N from on time to the
// end of what the guard covers (reply time-out + late guard), with Set Filter accepted and
// with every Set Filter NAKed. Each N gets a fresh driver, whose time-out has not adapted yet
// (the worst case), and then a second write with the time-out it adapted. Whatever happens to
// each write, the gateway must never report one applied that the sensor did not ACK (its
// filter changed), nor one the sensor NAKed.
TEST_CASE("a late sensor never has a write reported applied that it did not accept") {
  constexpr auto kTimeout = 40ms;
  constexpr auto kGuard = 80ms;
  Bench bench([&](SerialLineOptions& o) {
    o.timeout = kTimeout;
    o.late_guard = kGuard;
    o.retries = 1;
  });
  const std::vector<int> lateness_ms = {0, 10, 20, 30, 35, 40, 45, 50, 60, 70, 80, 90, 100, 110};
  int applied = 0;
  int applied_late = 0;  // by a sensor answering after the bus's time-out
  std::uint32_t late_replies = 0;
  for (const bool naked : {false, true}) {
    for (const int late : lateness_ms) {
      RiekerDriver driver(driver_options({kTimeout, 400ms}));
      bench.sensor().faults().reply_delay = std::chrono::milliseconds(late);
      faults_of(bench, Function::set_filter).nak = naked ? 1000 : 0;  // every one, retries too
      for (const char* write : {"first", "adapted"}) {
        CAPTURE(naked);
        CAPTURE(late);
        CAPTURE(write);
        const int filter = bench.sensor().filter();
        const int wanted = filter == 2 ? 3 : 2;
        const auto result = bench.write(driver, WriteTarget::filter, wanted);
        bench.drain(std::chrono::milliseconds(late) + 60ms);
        if (result) {
          ++applied;
          if (late >= kTimeout.count()) ++applied_late;
          CHECK_FALSE(naked);
          CHECK(bench.sensor().filter() == wanted);
        }
        if (naked) CHECK(bench.sensor().filter() == filter);
      }
      late_replies += driver.state().counters.late_replies;
    }
  }
  // The sweep is only worth something if writes did go through, late ones too, and late
  // replies were seen.
  CHECK(applied >= 5);
  CHECK(applied_late >= 3);
  CHECK(late_replies > 0);
}

TEST_CASE("a sensor 300 ms late gets a longer time-out, stays online and does not flap") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 50ms;
    o.late_guard = 300ms;
    o.retries = 1;
  });
  RiekerDriver driver(driver_options({50ms, 500ms}));
  bench.sensor().faults().reply_delay = 300ms;
  int transitions = 0;
  bool online = false;
  for (int i = 0; i < 10; ++i) {
    bench.poll(driver);
    if (driver.state().online != online) ++transitions;
    online = driver.state().online;
  }
  const SensorState& state = driver.state();
  CHECK(state.online);
  CHECK(transitions <= 1);  // offline at first, then online for good
  CHECK(state.counters.polls_ok >= 8);
  CHECK(state.counters.late_replies > 0);
  CHECK(state.answers_late);
  CHECK(state.reply_timeout > 300ms);
  CHECK(state.reply_timeout <= 500ms);
  CHECK(bench.line->stats().late_replies == state.counters.late_replies);
}

TEST_CASE("an offline sensor is probed with one attempt, without retries") {
  Bench bench([](SerialLineOptions& o) {
    o.retries = 2;
    o.late_guard = 30ms;
  });
  RiekerDriver driver(driver_options());
  bench.sensor().faults().silent = 1000;
  bench.poll(driver);  // the first poll after start gets the bus's retries
  CHECK_FALSE(driver.state().online);
  CHECK(bench.sensor().requests_handled() == 3);
  bench.poll(driver);  // offline now: one attempt, since each retry would cost the guard too
  CHECK(bench.sensor().requests_handled() == 4);
  bench.sensor().faults().silent = 0;
  bench.poll(driver);
  CHECK(driver.state().online);
}
