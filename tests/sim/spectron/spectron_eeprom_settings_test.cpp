// The Dyna's settings read back from its EEPROM ("3" / 0x69) and the EEPROM window, over a
// real SerialLine against the simulator, in both protocols.
#include <doctest/doctest.h>

#include <optional>
#include <vector>

#include "sim/support/dyna_bench.h"
#include "spectron/dyna_driver.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;
using namespace tiltgate::spectron;
using test::Bench;
using test::driver_for;
using test::dyna;
using test::kAddress;
using test::ModbusAscii;
using test::NineBit;

namespace {

std::optional<double> known_setting(const SensorDriver& driver, WriteTarget target) {
  return driver.state().settings.get(target);
}

DynaDriverOptions with_reserved_writes(Protocol protocol) {
  DynaDriverOptions options = driver_for(protocol);
  options.reserved_writes = true;
  return options;
}

}  // namespace

TEST_CASE_TEMPLATE("the EEPROM settings are read back with the identity", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  SimulatedDyna& module = bench.module();
  module.set_eeprom(6, 12);
  module.set_eeprom(10, 65535);
  module.set_eeprom(20, 2501);
  DynaDriver driver(driver_for(P::protocol));
  CHECK_FALSE(known_setting(driver, spectron::setting::sensor_offset).has_value());
  bench.poll(driver);
  CHECK(known_setting(driver, spectron::setting::sensor_offset) == 12);
  CHECK(known_setting(driver, spectron::setting::temperature_offset) == 65535);
  CHECK(known_setting(driver, spectron::setting::pwm_offset) == 2501);
  CHECK(known_setting(driver, WriteTarget::baud_code) == 10);  // the simulator's factory code
  CHECK(known_setting(driver, WriteTarget::bus_address) == kAddress);
  CHECK_FALSE(known_setting(driver, spectron::setting::eeprom_location).has_value());  // none selected

  // After a write: what the module holds, read back.
  CHECK(bench.write(driver, spectron::setting::pwm_offset, 7).has_value());
  CHECK(known_setting(driver, spectron::setting::pwm_offset) == 7);
  // Changed behind the gateway's back: seen again after a reset re-reads the identity.
  module.set_eeprom(6, 99);
  CHECK(bench.write(driver, WriteTarget::command, 1).has_value());
  bench.poll(driver);
  CHECK(known_setting(driver, spectron::setting::sensor_offset) == 99);
}

TEST_CASE_TEMPLATE("a module back from offline has its EEPROM settings read again", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  SimulatedDyna& module = bench.module();
  module.set_eeprom(6, 12);
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  REQUIRE(known_setting(driver, spectron::setting::sensor_offset) == 12);
  // Silent (both attempts of the measurement), and changed meanwhile by another tool.
  module.faults().silent = 2;
  bench.poll(driver);
  REQUIRE(known_offline(driver.state()));
  module.set_eeprom(6, 34);
  bench.poll(driver);  // answers again
  CHECK(driver.state().online);
  bench.poll(driver);
  CHECK(known_setting(driver, spectron::setting::sensor_offset) == 34);
}

TEST_CASE_TEMPLATE("a change another door made is read back from the module", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  SimulatedDyna& module = bench.module();
  module.set_eeprom(20, 5);
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  REQUIRE(known_setting(driver, spectron::setting::pwm_offset) == 5);
  // `tiltgate set` through the gateway wrote 40 and the module took 41 (say): the record holds
  // what the module holds, read at the next poll.
  module.set_eeprom(20, 41);
  driver.note_acknowledged(spectron::setting::pwm_offset, 40);
  bench.poll(driver);
  CHECK(known_setting(driver, spectron::setting::pwm_offset) == 41);
}

TEST_CASE_TEMPLATE("selecting a window location reads it from the module", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  SimulatedDyna& module = bench.module();
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  module.set_eeprom(20, 111);
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 20).has_value());
  CHECK(known_setting(driver, spectron::setting::eeprom_location) == 20);
  CHECK(known_setting(driver, spectron::setting::eeprom_value) == 111);
  CHECK(known_setting(driver, spectron::setting::pwm_offset) == 111);  // the same word, named
  module.set_eeprom(20, 222);  // not the last value written: the module's
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 20).has_value());
  CHECK(known_setting(driver, spectron::setting::eeprom_value) == 222);
  module.set_eeprom(140, 9);  // a reserved location reads like any other
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 140).has_value());
  CHECK(known_setting(driver, spectron::setting::eeprom_value) == 9);
  // A value written through the window is read back too.
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 10).has_value());
  CHECK(bench.write(driver, spectron::setting::eeprom_value, 5).has_value());
  CHECK(known_setting(driver, spectron::setting::eeprom_value) == 5);
  CHECK(known_setting(driver, spectron::setting::temperature_offset) == 5);
}

TEST_CASE_TEMPLATE("a selection the module does not answer leaves the old one", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 20).has_value());
  bench.module().faults().silent = 2;  // both attempts
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 6).error().kind ==
        WriteErrorKind::no_response);
  CHECK(driver.eeprom_location() == std::optional<std::uint16_t>(20));
}

TEST_CASE_TEMPLATE("reserved locations are writable only with eeprom_reserved_writes", P,
                   NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  SimulatedDyna& module = bench.module();
  DynaDriver strict(driver_for(P::protocol));
  CHECK(bench.write(strict, spectron::setting::eeprom_location, 100).has_value());
  CHECK(bench.write(strict, spectron::setting::eeprom_value, 355).error().kind ==
        WriteErrorKind::bad_value);
  CHECK(module.eeprom(100) == std::optional<std::uint16_t>(0));

  // The application note's example: 355 to location 100.
  DynaDriver allowed(with_reserved_writes(P::protocol));
  CHECK(bench.write(allowed, spectron::setting::eeprom_location, 100).has_value());
  CHECK(bench.write(allowed, spectron::setting::eeprom_value, 355).has_value());
  CHECK(module.eeprom(100) == std::optional<std::uint16_t>(355));
  CHECK(known_setting(allowed, spectron::setting::eeprom_value) == 355);
  CHECK(bench.write(allowed, spectron::setting::eeprom_location, 280).has_value());
  CHECK(bench.write(allowed, spectron::setting::eeprom_value, 1).has_value());
  CHECK(module.eeprom(280) == std::optional<std::uint16_t>(1));
  // Odd locations and the listed reserved ones stay refused.
  CHECK(allowed.check_write(spectron::setting::eeprom_location, 101).error().kind ==
        WriteErrorKind::bad_value);
  CHECK(bench.write(allowed, spectron::setting::eeprom_location, 8).has_value());
  CHECK(bench.write(allowed, spectron::setting::eeprom_value, 1).error().kind ==
        WriteErrorKind::bad_value);
}

TEST_CASE_TEMPLATE("location and value in one request: a refused value leaves the location", P,
                   NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 20).has_value());
  const auto value_at_20 = known_setting(driver, spectron::setting::eeprom_value);
  const auto handled = bench.module().requests_handled();

  // Checked against the new location before anything is sent (through the interface the
  // gateway uses): 100 is reserved.
  const SensorDriver& checker = driver;
  const std::vector<SettingWrite> reserved{{spectron::setting::eeprom_location, 100},
                                           {spectron::setting::eeprom_value, 355}};
  CHECK(checker.check_writes(reserved).error().kind == WriteErrorKind::bad_value);
  // ... and an acceptable value for the old location does not pass for the new one.
  const std::vector<SettingWrite> baud{{spectron::setting::eeprom_location, 22},
                                       {spectron::setting::eeprom_value, 355}};
  CHECK(checker.check_writes(baud).error().kind == WriteErrorKind::bad_value);
  CHECK(bench.module().requests_handled() == handled);
  const std::vector<SettingWrite> fine{{spectron::setting::eeprom_location, 22},
                                       {spectron::setting::eeprom_value, 15}};
  CHECK(checker.check_writes(fine).has_value());

  // Refused by the module (here: not answered): the selection goes back.
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 6).has_value());
  bench.module().faults().silent = 2;
  CHECK_FALSE(bench.write(driver, spectron::setting::eeprom_value, 5).has_value());
  const std::vector<SettingWrite> selected{{spectron::setting::eeprom_location, 6}};
  driver.abandon(selected);
  CHECK(driver.eeprom_location() == std::optional<std::uint16_t>(20));
  CHECK(known_setting(driver, spectron::setting::eeprom_value) == value_at_20);
}
