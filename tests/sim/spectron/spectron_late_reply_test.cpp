// A Dyna on Modbus-ASCII that answers after the reply time-out: its late reply is discarded and
// counted, never taken as the answer to the next request (the same command's reply, a poll
// later, carries the same address and command, so only the line's guard can tell them apart).
#include <doctest/doctest.h>

#include "serial/serial_line.h"
#include "sim/support/captured_log.h"
#include "sim/support/driver_bench.h"
#include "spectron/dyna_driver.h"
#include "spectron/simulator.h"

using namespace tiltgate;
using namespace tiltgate::spectron;
using namespace std::chrono_literals;

namespace {

constexpr std::uint8_t kAddress = 7;

struct Bench : test::DriverBench<DynaSimulator> {
  explicit Bench(const std::function<void(SerialLineOptions&)>& adjust)
      : DriverBench(simulator_options(), line_options(), adjust) {}

  static DynaSimulatorOptions simulator_options() {
    SimulatedDynaOptions module;
    module.address = kAddress;
    module.counts = 1000;
    DynaSimulatorOptions options;
    options.protocol = Protocol::modbus_ascii;
    options.sensors = {module};
    return options;
  }
  static SerialLineOptions line_options() {
    SerialLineOptions options;
    options.name = "dyna-line";
    options.baud = 28800;
    options.framing = Framing::eight_even_one;
    return options;
  }
  SimulatedDyna& module() { return sim->sensor(0); }
};

DynaDriverOptions driver_options(ReplyTimeouts timeouts) {
  DynaDriverOptions options;
  options.name = "dyna";
  options.protocol = Protocol::modbus_ascii;
  options.address = kAddress;
  options.counts_per_degree = 1.0;
  options.reply_timeouts = timeouts;
  return options;
}

}  // namespace

TEST_CASE("a Dyna's late reply is not taken as the answer to the next poll") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 50ms;
    o.late_guard = 200ms;
    o.retries = 0;
  });
  // Time-out equal to the cap: this test is about the guard, not about adapting.
  DynaDriver driver(driver_options({50ms, 50ms}));
  bench.poll(driver);  // identity and a first reading, on time
  REQUIRE(driver.state().counters.polls_ok == 1);

  bench.module().faults().by_command[AsciiCommand::read_sensor].delay = 120ms;
  bench.poll(driver);  // read sensor times out; its reply (1000 counts) comes 70 ms late
  CHECK(driver.state().counters.polls_failed == 1);
  CHECK(driver.state().counters.late_replies == 1);

  bench.module().faults().by_command.clear();
  bench.module().set_counts(2000);
  bench.poll(driver);
  CHECK(driver.state().counters.polls_ok == 2);
  REQUIRE(driver.state().reading.has_value());
  CHECK(driver.state().reading->raw_counts == 2000);
}

namespace {

// A 50 ms reply wait that a late reply (150 ms) makes the driver adapt, up to 400 ms.
void adaptive_line(SerialLineOptions& o) {
  o.timeout = 50ms;
  o.late_guard = 200ms;
  o.retries = 1;
}

}  // namespace

TEST_CASE("a Dyna that answers late on every command gets a longer time-out") {
  Bench bench(adaptive_line);
  DynaDriver driver(driver_options({50ms, 400ms}));
  bench.module().faults().reply_delay = 150ms;
  for (int i = 0; i < 4; ++i) bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().answers_late);
  CHECK(driver.state().reply_timeout > 150ms);
  CHECK(driver.state().counters.polls_ok >= 3);
}

TEST_CASE("a sensor late again within 10 minutes is not warned of twice, time-out changes are debug") {
  test::CapturedLog log(spdlog::level::debug);
  Bench bench(adaptive_line);
  DynaDriver driver(driver_options({50ms, 400ms}));
  bench.module().faults().reply_delay = 150ms;
  for (int i = 0; i < 3; ++i) bench.poll(driver);
  REQUIRE(driver.state().answers_late);
  bench.module().faults().reply_delay = 0ms;
  for (int i = 0; i < 2 * 50 && driver.state().answers_late; ++i) bench.poll(driver);
  REQUIRE_FALSE(driver.state().answers_late);
  bench.module().faults().reply_delay = 150ms;
  for (int i = 0; i < 3; ++i) bench.poll(driver);
  REQUIRE(driver.state().answers_late);
  const auto level_of = [&](const std::string& text) {
    std::vector<std::string> levels;
    for (const std::string& line : log.lines())
      if (line.find(text) != std::string::npos) levels.push_back(line.substr(0, line.find(' ')));
    return levels;
  };
  CHECK(level_of("answers late") == std::vector<std::string>{"warning", "debug"});
  CHECK(level_of("answers in time again") == std::vector<std::string>{"info"});
  const std::vector<std::string> timeouts = level_of("reply time-out");
  CHECK_FALSE(timeouts.empty());
  for (const std::string& level : timeouts) CHECK(level == "debug");
}
