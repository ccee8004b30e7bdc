// The Dyna driver over a real SerialLine on a pseudo-terminal, against the Dyna simulator, in
// both protocols: 9-bit addressing (mark/space framing) and Modbus-ASCII (8E1, LRC).
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cmath>
#include <memory>
#include <optional>

#include "serial/serial_line.h"
#include "sim/support/raw_tty_client.h"
#include "sim/support/dyna_bench.h"
#include "sim/support/run_coroutine.h"
#include "spectron/ascii_codec.h"
#include "spectron/dyna_driver.h"
#include "spectron/simulator.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;
using namespace tiltgate::spectron;
using namespace std::chrono_literals;
using test::run_coroutine;

namespace {

using test::Bench;
using test::driver_for;
using test::dyna;
using test::kAddress;
using test::ModbusAscii;
using test::NineBit;

WriteErrorKind kind_of(const WriteResult& result) {
  REQUIRE_FALSE(result.has_value());
  return result.error().kind;
}

}  // namespace

TEST_CASE_TEMPLATE("a first poll reads the identity, then counts and temperature as degrees", P,
                   NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  const SensorState& s = driver.state();
  CHECK(s.online);
  CHECK(s.identity_known);
  CHECK(s.serial == "12345");  // EEPROM 4, as decimal text
  CHECK(s.firmware == P::firmware);
  CHECK_FALSE(s.protection_level.has_value());  // the Dyna has no locks
  REQUIRE(s.reading.has_value());
  CHECK(s.reading->raw_counts == std::optional<std::int32_t>(1001));
  CHECK(s.reading->raw_temperature == std::optional<std::int32_t>(-40));
  CHECK(s.reading->angle_x == doctest::Approx(10.0));  // (1001 - 1) / 100
  CHECK(std::isnan(s.reading->angle_y));
  // The assumed 0.1 degC per count (docs/protocols.md, "Dyna: what the note leaves open").
  REQUIRE(s.reading->temperature_c.has_value());
  CHECK(*s.reading->temperature_c == doctest::Approx(-4.0));
  CHECK(s.sample_seq == 1);
  // firmware, serial, the five EEPROM settings, sensor, temperature
  CHECK(s.counters.transactions == 9);
  bench.poll(driver);
  CHECK(s.counters.transactions == 11);  // identity is not read again
  CHECK(s.counters.polls_ok == 2);
  CHECK(s.sample_seq == 2);
}

TEST_CASE_TEMPLATE("negative counts convert to negative degrees", P, NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna(kAddress, -2499)});
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  REQUIRE(driver.state().reading.has_value());
  CHECK(driver.state().reading->raw_counts == std::optional<std::int32_t>(-2499));
  CHECK(driver.state().reading->angle_x == doctest::Approx(-25.0));
}

TEST_CASE_TEMPLATE("the temperature counts convert by the sensor's own temperature keys", P,
                   NineBit, ModbusAscii) {
  SimulatedDynaOptions module = dyna();
  module.temperature = 523;
  Bench bench(P::protocol, {module});
  DynaDriverOptions options = driver_for(P::protocol);
  options.temperature_counts_per_degree = 20.0;  // 0.05 degC per count
  options.temperature_zero_counts = 100.0;
  DynaDriver driver(options);
  bench.poll(driver);
  REQUIRE(driver.state().reading.has_value());
  CHECK(driver.state().reading->raw_temperature == std::optional<std::int32_t>(523));
  CHECK(driver.state().reading->temperature_c == std::optional<double>((523 - 100) / 20.0));
}

TEST_CASE_TEMPLATE("every named EEPROM setting and the EEPROM window reach the module", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  SimulatedDyna& module = bench.module();

  CHECK(bench.write(driver, spectron::setting::sensor_offset, 1).has_value());
  CHECK(module.eeprom(6) == std::optional<std::uint16_t>(1));
  bench.poll(driver);
  CHECK(driver.state().reading->raw_counts == std::optional<std::int32_t>(1000));
  CHECK(bench.write(driver, spectron::setting::temperature_offset, 65535).has_value());  // -1 as a word
  CHECK(module.eeprom(10) == std::optional<std::uint16_t>(65535));
  CHECK(bench.write(driver, spectron::setting::pwm_offset, 2501).has_value());  // the note's example value
  CHECK(module.eeprom(20) == std::optional<std::uint16_t>(2501));
  bench.poll(driver);
  CHECK(driver.state().reading->raw_temperature == std::optional<std::int32_t>(-39));

  CHECK(bench.write(driver, WriteTarget::baud_code, 15).has_value());
  CHECK(module.eeprom(22) == std::optional<std::uint16_t>(15));
  CHECK(module.baud_code() == 10);  // in force only after a reset

  // The window: select, then write.
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 20).has_value());
  CHECK(driver.eeprom_location() == std::optional<std::uint16_t>(20));
  CHECK(bench.write(driver, spectron::setting::eeprom_value, 355).has_value());
  CHECK(module.eeprom(20) == std::optional<std::uint16_t>(355));
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 6).has_value());
  CHECK(bench.write(driver, spectron::setting::eeprom_value, 0).has_value());
  CHECK(module.eeprom(6) == std::optional<std::uint16_t>(0));
  CHECK_FALSE(driver.state().last_write_failed);
}

TEST_CASE_TEMPLATE("the EEPROM window refuses before sending anything", P, NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  const auto& module = bench.module();
  auto handled = module.requests_handled();
  CHECK(kind_of(bench.write(driver, spectron::setting::eeprom_value, 1)) == WriteErrorKind::bad_value);
  CHECK(module.requests_handled() == handled);
  // Selecting reads the location (one request); the refused values send nothing.
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 4).has_value());  // documented ...
  handled = module.requests_handled();
  CHECK(kind_of(bench.write(driver, spectron::setting::eeprom_value, 1)) ==
        WriteErrorKind::bad_value);  // ... but the serial number is read-only
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 100).has_value());
  CHECK(module.requests_handled() == handled + 1);
  handled = module.requests_handled();
  CHECK(kind_of(bench.write(driver, spectron::setting::eeprom_value, 355)) ==
        WriteErrorKind::bad_value);  // reserved: read-only without eeprom_reserved_writes
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 22).has_value());
  handled = module.requests_handled();
  CHECK(kind_of(bench.write(driver, spectron::setting::eeprom_value, 8)) == WriteErrorKind::bad_value);
  CHECK(kind_of(bench.write(driver, spectron::setting::eeprom_location, 24)) ==
        WriteErrorKind::bad_value);  // not in the memory map
  CHECK(driver.eeprom_location() == std::optional<std::uint16_t>(22));
  CHECK(module.requests_handled() == handled);
  CHECK(bench.module().eeprom(4) == std::optional<std::uint16_t>(12345));
  CHECK(bench.module().eeprom(100) == std::optional<std::uint16_t>(0));
}

TEST_CASE_TEMPLATE("a module address change is followed to the new address", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  CHECK(bench.write(driver, WriteTarget::bus_address, 42).has_value());
  CHECK(bench.sim->sensor_by_address(42) != nullptr);
  CHECK(driver.address() == 42);
  CHECK(driver.state().bus_address == 42);
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().counters.polls_ok == 1);
  // Through the window too, and back.
  CHECK(bench.write(driver, spectron::setting::eeprom_location, 16).has_value());
  CHECK(bench.write(driver, spectron::setting::eeprom_value, kAddress).has_value());
  CHECK(driver.address() == kAddress);
  bench.poll(driver);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE_TEMPLATE("an ignored address change fails with no response and the driver stays", P,
                   NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  bench.module().faults().silent = 1;  // the write is never taken in, and never retried
  CHECK(kind_of(bench.write(driver, WriteTarget::bus_address, 42)) ==
        WriteErrorKind::no_response);
  CHECK(driver.address() == kAddress);
  CHECK(bench.module().address() == kAddress);
  CHECK(driver.state().last_write_failed);
  bench.poll(driver);
  CHECK(driver.state().online);
}

TEST_CASE("Modbus-ASCII: an address change whose acknowledgement is lost is found at the new one") {
  Bench bench(Protocol::modbus_ascii, {dyna()});
  DynaDriver driver(driver_for(Protocol::modbus_ascii));
  bench.module().faults().corrupt_lrc = 1;  // the module moves, its acknowledgement is dropped
  CHECK(bench.write(driver, WriteTarget::bus_address, 42).has_value());
  CHECK(driver.address() == 42);
  CHECK(driver.state().counters.checksum_errors == 1);
  bench.poll(driver);
  CHECK(driver.state().counters.polls_ok == 1);
}

TEST_CASE_TEMPLATE("a reset is sent, and the identity is read again afterwards", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  REQUIRE(driver.state().identity_known);
  CHECK(bench.write(driver, WriteTarget::baud_code, 32).has_value());
  CHECK(bench.write(driver, WriteTarget::command, 1).has_value());
  CHECK(bench.module().resets() == 1);
  CHECK(bench.module().baud_code() == 32);  // the stored code is now in force
  CHECK_FALSE(driver.state().identity_known);
  const auto transactions = driver.state().counters.transactions;
  bench.poll(driver);
  CHECK(driver.state().identity_known);
  CHECK(driver.state().counters.transactions == transactions + 9);  // identity, settings, reading
}

TEST_CASE("values a Dyna cannot take are refused before anything is sent") {
  DynaDriver nine_bit(driver_for(Protocol::nine_bit));
  DynaDriver modbus(driver_for(Protocol::modbus_ascii));
  const auto refused = [](const DynaDriver& driver, WriteTarget target, double value) {
    const auto checked = driver.check_write(target, value);
    return checked ? std::optional<WriteErrorKind>() : checked.error().kind;
  };
  const auto bad = std::optional<WriteErrorKind>(WriteErrorKind::bad_value);
  const auto ok = std::optional<WriteErrorKind>();
  for (auto target :
       {spectron::setting::sensor_offset, spectron::setting::temperature_offset, spectron::setting::pwm_offset}) {
    CHECK(refused(modbus, target, 0) == ok);
    CHECK(refused(modbus, target, 65535) == ok);
    CHECK(refused(modbus, target, 65536) == bad);
    CHECK(refused(modbus, target, -1) == bad);
    CHECK(refused(modbus, target, 1.5) == bad);
    CHECK(refused(modbus, target, NAN) == bad);
  }
  for (int code : {7, 10, 15, 32, 64}) CHECK(refused(modbus, WriteTarget::baud_code, code) == ok);
  CHECK(refused(modbus, WriteTarget::baud_code, 8) == bad);
  CHECK(refused(modbus, WriteTarget::bus_address, 0) == bad);  // Modbus-ASCII: 1..250
  CHECK(refused(modbus, WriteTarget::bus_address, 251) == bad);
  CHECK(refused(modbus, WriteTarget::bus_address, 250) == ok);
  CHECK(refused(nine_bit, WriteTarget::bus_address, 0) == ok);  // 9-bit: 0..255
  CHECK(refused(nine_bit, WriteTarget::bus_address, 255) == ok);
  CHECK(refused(nine_bit, WriteTarget::bus_address, 256) == bad);
  CHECK(refused(modbus, WriteTarget::command, 1) == ok);
  CHECK(refused(modbus, WriteTarget::command, 3) == bad);
  CHECK(refused(modbus, spectron::setting::eeprom_location, 4) == ok);    // documented, read-only
  CHECK(refused(modbus, spectron::setting::eeprom_location, 280) == ok);  // reserved block
  CHECK(refused(modbus, spectron::setting::eeprom_location, 5) == bad);   // odd
  CHECK(refused(modbus, spectron::setting::eeprom_location, 24) == bad);  // not in the map
  CHECK(refused(modbus, spectron::setting::eeprom_location, 282) == bad);
  CHECK(refused(modbus, spectron::setting::eeprom_value, 65536) == bad);
  CHECK(refused(modbus, WriteTarget::filter, 1) ==
        std::optional<WriteErrorKind>(WriteErrorKind::not_supported));
  CHECK(refused(modbus, WriteTarget::zero_x, 0) ==
        std::optional<WriteErrorKind>(WriteErrorKind::not_supported));
}

TEST_CASE_TEMPLATE("a silent module times out, goes offline, and comes back", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()}, /*retries=*/1);
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  REQUIRE(driver.state().online);
  bench.module().faults().silent = 2;  // both attempts of the next exchange
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
  CHECK(driver.state().counters.polls_failed == 1);
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE_TEMPLATE("noise on the line before a reply does not lose the reply", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
  bench.module().faults().garbage = 4;  // before every reply of the first poll
  bench.poll(driver);
  CHECK(driver.state().identity_known);
  CHECK(driver.state().counters.polls_ok == 1);
  CHECK(driver.state().counters.timeouts == 0);
}

TEST_CASE("Modbus-ASCII: a reply with a bad LRC is counted and the retry succeeds") {
  Bench bench(Protocol::modbus_ascii, {dyna()}, /*retries=*/2);
  DynaDriver driver(driver_for(Protocol::modbus_ascii));
  bench.poll(driver);
  bench.module().faults().corrupt_lrc = 1;
  bench.poll(driver);
  CHECK(driver.state().counters.checksum_errors == 1);
  CHECK(driver.state().counters.timeouts == 0);  // the retry got it
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE("Modbus-ASCII: a reply that is not the acknowledgement refuses the write") {
  Bench bench(Protocol::modbus_ascii, {dyna()});
  DynaDriver driver(driver_for(Protocol::modbus_ascii));
  // A well-framed answer to the write that carries a data word: not ":AA68LRC".
  const auto wrong = encode(make_ascii_word_reply(kAddress, AsciiCommand::write_eeprom, 1));
  bench.module().faults().garbage_bytes.assign(wrong.begin(), wrong.end());
  bench.module().faults().garbage = 1;
  CHECK(kind_of(bench.write(driver, spectron::setting::sensor_offset, 5)) == WriteErrorKind::refused);
  CHECK(driver.state().last_write_failed);
  CHECK(driver.state().online);  // it answered
}

TEST_CASE("9-bit: a reply line that is not a number fails the poll, the module stays online") {
  Bench bench(Protocol::nine_bit, {dyna()});
  DynaDriver driver(driver_for(Protocol::nine_bit));
  bench.poll(driver);
  const std::string text = "ERR\r\n";
  bench.module().faults().garbage_bytes.assign(text.begin(), text.end());
  bench.module().faults().garbage = 1;  // the read sensor reply starts with another line
  bench.poll(driver);
  CHECK(driver.state().online);
  CHECK(driver.state().counters.polls_failed == 1);
  bench.poll(driver);
  CHECK(driver.state().counters.polls_ok == 2);
}

TEST_CASE_TEMPLATE("a module on another address is silent to this driver", P, NineBit,
                   ModbusAscii) {
  Bench bench(P::protocol, {dyna(8)}, /*retries=*/0);
  DynaDriver driver(driver_for(P::protocol));
  bench.poll(driver);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
}

TEST_CASE_TEMPLATE("an unplugged adapter fails polls, and after the replug identity is read again",
                   P, NineBit, ModbusAscii) {
  Bench bench(P::protocol, {dyna()});
  DynaDriver driver(driver_for(P::protocol));
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
  CHECK(driver.state().counters.transactions == transactions + 9);  // identity again + reading
}
