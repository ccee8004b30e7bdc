// The Modbus RTU driver against the RTU simulator over a pseudo-terminal, with the example
// device profile examples/devices/rtu-inclinometer.toml: angles read, a silent slave goes
// offline and comes back, a bad CRC is counted, an exception reply is a refusal.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/profile_reader.h"
#include "modbus_rtu/rtu_driver.h"
#include "modbus_rtu/simulator/simulator.h"
#include "sim/support/driver_bench.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;

namespace {

// One RTU bus, 8E1 at 19200 baud, with one inclinometer at slave 5.
struct Bench : test::DriverBench<RtuSimulator> {
  explicit Bench(double angle_x, double angle_y, int retries = 0)
      : DriverBench(simulator_options(angle_x, angle_y), line_options(retries)) {}

  static RtuSimulatorOptions simulator_options(double angle_x, double angle_y) {
    RtuSimulatorOptions options;
    options.devices.push_back(rtu_inclinometer(5));
    set_inclinometer_angles(options.devices.back(), angle_x, angle_y);
    return options;
  }
  static SerialLineOptions line_options(int retries) {
    SerialLineOptions options;
    options.name = "rtu1";
    options.baud = 19200;
    options.framing = Framing::eight_even_one;
    options.retries = retries;
    return options;
  }
  SimulatedDevice& device() { return *sim->device(5); }
};

DeviceProfile example_profile() {
  auto profile = load_device_profile(std::string(TILTGATE_SOURCE_DIR) +
                                     "/examples/devices/rtu-inclinometer.toml");
  REQUIRE(profile.has_value());
  return *profile;
}

RtuDriver driver_for(DeviceProfile profile) {
  RtuDriverOptions options;
  options.name = "tilt";
  options.slave = 5;
  options.profile = std::move(profile);
  options.reply_timeouts = test::kBenchReplyTimeouts;
  return RtuDriver(std::move(options));
}

}  // namespace

TEST_CASE("the RTU driver reads the profile's angle_x and angle_y from the slave") {
  Bench bench(1.25, -3.5);
  RtuDriver driver = driver_for(example_profile());
  bench.poll(driver);
  const SensorState& state = driver.state();
  REQUIRE(state.reading.has_value());
  CHECK(state.reading->angle_x == doctest::Approx(1.25));
  CHECK(state.reading->angle_y == doctest::Approx(-3.5));
  CHECK(state.online);
  CHECK(state.identity_known);
  CHECK(state.counters.polls_ok == 1);
  // The identity's block (holding 0..4: serial, firmware, model), then the two read blocks.
  CHECK(state.counters.transactions == 3);
  CHECK(state.serial == "20240917");
  CHECK(state.firmware == "1.02");
  // The profile's model_name, not the model number the device reports (360).
  CHECK(state.model == "RTU inclinometer");
  set_inclinometer_angles(bench.device(), -0.5, 0.75);
  bench.poll(driver);
  CHECK(driver.state().reading->angle_x == doctest::Approx(-0.5));
  CHECK(driver.state().sample_seq == 2);
  CHECK(driver.state().counters.transactions == 5);  // the identity is not read again
}

TEST_CASE("without a model_name, the model is the [identity] model value the device reports") {
  Bench bench(1.0, 2.0);
  DeviceProfile profile = example_profile();
  profile.model_name.clear();
  RtuDriver driver = driver_for(std::move(profile));
  CHECK(driver.state().model.empty());  // nothing to show before the identity is read
  bench.poll(driver);
  CHECK(driver.state().model == "360");
}

TEST_CASE("a profile's value named temperature is the reading's temperature in degC") {
  Bench bench(1.0, 2.0);  // the preset's 21.5 degC, as an int16 of tenths at input 6
  RtuDriver with = driver_for(example_profile());
  bench.poll(with);
  REQUIRE(with.state().reading.has_value());
  REQUIRE(with.state().reading->temperature_c.has_value());
  CHECK(*with.state().reading->temperature_c == doctest::Approx(21.5));

  DeviceProfile profile = example_profile();
  std::erase_if(profile.values, [](const ProfileValue& v) { return v.name == "temperature"; });
  RtuDriver without = driver_for(std::move(profile));
  bench.poll(without);
  REQUIRE(without.state().reading.has_value());
  CHECK_FALSE(without.state().reading->temperature_c.has_value());
}

TEST_CASE("a profile without angles publishes readings with NaN angles") {
  Bench bench(1.0, 2.0);
  DeviceProfile profile = example_profile();
  std::erase_if(profile.values, [](const ProfileValue& v) { return v.name.starts_with("angle"); });
  RtuDriver driver = driver_for(std::move(profile));
  bench.poll(driver);
  REQUIRE(driver.state().reading.has_value());
  CHECK(std::isnan(driver.state().reading->angle_x));
  CHECK(std::isnan(driver.state().reading->angle_y));
}

TEST_CASE("a silent RTU slave goes offline and comes back") {
  Bench bench(1.0, 2.0);
  RtuDriver driver = driver_for(example_profile());
  bench.poll(driver);
  REQUIRE(driver.state().online);
  bench.device().faults().silent = 1;
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
  CHECK(driver.state().counters.polls_failed == 1);
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE("a reply with a bad CRC is counted and the poll fails") {
  Bench bench(1.0, 2.0);
  RtuDriver driver = driver_for(example_profile());
  bench.device().faults().corrupt_crc = 1;
  bench.poll(driver);
  CHECK(driver.state().counters.checksum_errors == 1);
  CHECK(driver.state().counters.polls_failed == 1);
  CHECK_FALSE(driver.state().reading.has_value());
}

TEST_CASE("an exception reply is counted as a refusal by its code and fails the poll") {
  Bench bench(1.0, 2.0);
  DeviceProfile profile = example_profile();
  profile.reads.push_back(ReadBlock{RegisterBank::holding, 100, 2});  // past the preset's registers
  RtuDriver driver = driver_for(std::move(profile));
  bench.poll(driver);
  const SensorCounters& counters = driver.state().counters;
  CHECK(counters.refusals[2] == 1);  // 02 illegal data address
  CHECK(counters.last_refusal == std::optional<std::uint8_t>(2));
  CHECK(counters.polls_failed == 1);
  CHECK(driver.state().online);  // it answered
  CHECK_FALSE(driver.state().reading.has_value());
}

TEST_CASE("the RTU driver refuses writes as not supported") {
  Bench bench(1.0, 2.0);
  RtuDriver driver = driver_for(example_profile());
  auto written = bench.write(driver, WriteTarget::filter, 3);
  REQUIRE_FALSE(written.has_value());
  CHECK(written.error().kind == WriteErrorKind::not_supported);
}
