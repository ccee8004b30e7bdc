// Writes of a device profile's writable values through the Modbus RTU driver, against the RTU
// simulator over a pseudo-terminal: FC 6 for one register, FC 16 for two, answered after the
// device's reply; out-of-range values refused before anything is sent; the device's own
// exception relayed with its code. Reads publish every profile value.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/profile_reader.h"
#include "modbus_rtu/rtu_driver.h"
#include "modbus_rtu/simulator/simulator.h"
#include "sim/support/driver_bench.h"
#include "unit/support/rtu_test_profile.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;

namespace {

constexpr std::size_t kTemperature = test::rtu_test_value::temperature;
constexpr std::size_t kFilterLevel = test::rtu_test_value::filter_level;
constexpr std::size_t kSerialNumber = test::rtu_test_value::serial_number;

struct Bench : test::DriverBench<RtuSimulator> {
  Bench() : DriverBench(simulator_options(), line_options()) {}

  static RtuSimulatorOptions simulator_options() {
    RtuSimulatorOptions options;
    options.devices.push_back(rtu_inclinometer(5));
    return options;
  }
  static SerialLineOptions line_options() {
    SerialLineOptions options;
    options.name = "rtu1";
    options.baud = 19200;
    options.framing = Framing::eight_even_one;
    options.retries = 0;
    return options;
  }
  SimulatedDevice& device() { return *sim->device(5); }
};

RtuDriver driver() {
  auto profile = parse_device_profile(test::kRtuTestProfile, "writes.toml");
  REQUIRE(profile.has_value());
  RtuDriverOptions options;
  options.name = "tilt";
  options.slave = 5;
  options.profile = std::move(*profile);
  options.reply_timeouts = test::kBenchReplyTimeouts;
  return RtuDriver(std::move(options));
}

}  // namespace

TEST_CASE("the RTU driver publishes every profile value with each reading") {
  Bench bench;
  RtuDriver rtu = driver();
  bench.poll(rtu);
  REQUIRE(rtu.state().reading.has_value());
  const auto& values = rtu.state().reading->device_values;
  REQUIRE(values.size() == 5);
  CHECK(values[kTemperature] == doctest::Approx(21.5));
  CHECK(values[kFilterLevel] == 4);
  CHECK(values[kSerialNumber] == 20240917);
}

TEST_CASE("a one-register profile value is written with FC 6 and read back") {
  Bench bench;
  RtuDriver rtu = driver();
  bench.poll(rtu);
  const auto written = bench.write(rtu, WriteTarget::device_value(kFilterLevel), 6);
  REQUIRE_MESSAGE(written.has_value(), written.error().detail);
  CHECK(bench.device().holding()[kInclinometerFilterRegister] == 6);
  CHECK(rtu.state().reading->device_values[kFilterLevel] == 6);  // before the next poll
  CHECK_FALSE(rtu.state().last_write_failed);
  bench.poll(rtu);
  CHECK(rtu.state().reading->device_values[kFilterLevel] == 6);
}

TEST_CASE("the device's exception to a write is relayed with its own code") {
  Bench bench;
  RtuDriver rtu = driver();
  bench.poll(rtu);
  // 12 is inside the profile's range but outside the device's 1..8: the device says 03.
  const auto refused = bench.write(rtu, WriteTarget::device_value(kFilterLevel), 12);
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().kind == WriteErrorKind::device_exception);
  CHECK(refused.error().device_exception == 0x03);
  CHECK(rtu.state().counters.last_refusal == std::optional<std::uint8_t>(0x03));
  CHECK(rtu.state().last_write_failed);
  CHECK(bench.device().holding()[kInclinometerFilterRegister] == 4);
  // The 32-bit serial number goes as one FC 16 request, which this device refuses too.
  const std::uint64_t before = bench.device().requests_handled();
  const auto serial = bench.write(rtu, WriteTarget::device_value(kSerialNumber), 7);
  REQUIRE_FALSE(serial.has_value());
  CHECK(serial.error().kind == WriteErrorKind::device_exception);
  CHECK(bench.device().requests_handled() == before + 1);
}

TEST_CASE("a write outside the profile's range is refused before anything is sent") {
  Bench bench;
  RtuDriver rtu = driver();
  bench.poll(rtu);
  const std::uint64_t before = bench.device().requests_handled();
  for (const double bad : std::vector<double>{21.0, -1.0, NAN, 1e300}) {
    const auto refused = bench.write(rtu, WriteTarget::device_value(kFilterLevel), bad);
    REQUIRE_FALSE(refused.has_value());
    CHECK(refused.error().kind == WriteErrorKind::bad_value);
  }
  for (const WriteTarget other : std::vector<WriteTarget>{
           WriteTarget::device_value(kTemperature), WriteTarget::filter,
           WriteTarget::device_value(40)}) {
    const auto refused = bench.write(rtu, other, 1);
    REQUIRE_FALSE(refused.has_value());
    CHECK(refused.error().kind == WriteErrorKind::not_supported);
  }
  CHECK(bench.device().requests_handled() == before);
}
