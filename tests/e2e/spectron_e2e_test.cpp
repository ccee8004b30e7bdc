// build/tiltgate run with a mixed plant in one process (tests/e2e/support/mixed_plant.h): Rieker
// sensors on a Rieker bus, a Dyna on a Modbus-ASCII bus and a Dyna on a 9-bit bus, each bus a
// simulator on its own pseudo-terminal, read and written with the real libmodbus client.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/mixed_plant.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using spectron::DynaSimulator;

TEST_CASE("a Dyna on each Spectron bus and a Rieker H6 are served by one process") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  auto words = client.input(0, 38);
  REQUIRE(words.size() == 38);
  CHECK(float_at(words, 0) == 10.0f);          // (1001 - 1) / 100
  CHECK(std::isnan(float_at(words, 2)));       // no Y
  CHECK(std::int16_t(words[4]) == 1000);       // hundredths
  CHECK(std::int16_t(words[5]) == -32768);     // no Y
  CHECK((words[6] & 0x0F) == 0x01);  // online, fresh, no failed write, identity known
  CHECK(words[12] == 65535);         // no NAK: the Dyna has none
  CHECK(words[13] == 65535);         // nor lock levels
  CHECK(words[14] == 1);             // module address
  CHECK(string_at(words, 16, 10) == "4242      ");
  CHECK(string_at(words, 21, 8) == "01.07   ");
  CHECK(words[37] == 3);  // model code: Dyna
  auto raw = client.input(100, 3);  // the Dyna's own points
  REQUIRE(raw.size() == 3);
  CHECK(std::int32_t(std::uint32_t(raw[0]) << 16 | raw[1]) == 1001);  // raw counts
  CHECK(std::int16_t(raw[2]) == -40);                                  // raw temperature
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{1});

  client.unit(kNineBitDynaUnit);
  words = client.input(0, 38);
  REQUIRE(words.size() == 38);
  CHECK(float_at(words, 0) == doctest::Approx(5.005));  // 1001 / 200
  CHECK(words[14] == 0);
  CHECK(string_at(words, 16, 10) == "4343      ");
  CHECK(string_at(words, 21, 8) == "V1.07   ");
  CHECK(client.input(102, 1) == std::vector<std::uint16_t>{std::uint16_t(-40)});

  client.unit(kRiekerUnit);
  words = client.input(0, 4);
  REQUIRE(words.size() == 4);
  CHECK(float_at(words, 0) == 1.5f);
  CHECK(float_at(words, 2) == -2.25f);
}

TEST_CASE("Dyna writes: a named offset and the EEPROM window reach the module") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  CHECK(client.write(100, 1));  // sensor offset, EEPROM 6
  CHECK(eeprom(*plant.modbus_sim, 6) == 1);
  CHECK(wait_input(client, 100, {0, 1000}));  // raw counts: the module now subtracts it
  CHECK(client.holding(100, 1) == std::vector<std::uint16_t>{1});

  // The EEPROM window, location and value in one request: the PWM offset, EEPROM 20, which
  // pwm_offset then shows too (read back from the module).
  CHECK(client.write(103, std::vector<std::uint16_t>{20, 355}));
  CHECK(eeprom(*plant.modbus_sim, 20) == 355);
  CHECK(client.holding(100, 5) == std::vector<std::uint16_t>{1, 0, 355, 20, 355});

  client.unit(kNineBitDynaUnit);  // the same through 9-bit addressing
  CHECK(client.write(102, 2501));  // PWM offset, EEPROM 20
  CHECK(eeprom(*plant.nine_bit_sim, 20) == 2501);
  CHECK(client.write(103, 10));  // the window: temperature offset, EEPROM 10
  CHECK(client.write(104, 5));
  CHECK(eeprom(*plant.nine_bit_sim, 10) == 5);
  CHECK(wait_input(client, 102, {std::uint16_t(-45)}));
}

TEST_CASE("Dyna writes the module cannot take are refused with 0x02 and 0x03") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  CHECK(client.write(103, 4));  // the serial number's location may be selected ...
  CHECK(client.holding(104, 1) == std::vector<std::uint16_t>{4242});  // ... and is read
  CHECK_FALSE(client.write(104, 1));
  CHECK(client.exception() == 0x03);  // ... but not written
  CHECK(eeprom(*plant.modbus_sim, 4) == 4242);
  CHECK(client.write(103, 100));  // reserved (the note's example location): read-only here
  CHECK_FALSE(client.write(104, 355));
  CHECK(client.exception() == 0x03);
  CHECK(eeprom(*plant.modbus_sim, 100) == 0);
  CHECK_FALSE(client.write(103, 5));  // odd
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(103, 24));  // not in the memory map
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(103, 300));  // beyond the register's range 2..280
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(0, 1));  // filter: a Rieker setting, not available on a Dyna
  CHECK(client.exception() == 0x02);
  CHECK_FALSE(client.write(6, 8));  // not one of the five baud codes
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(5, 2));  // the only command is 1
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(7, 251));  // Modbus-ASCII modules: 1..250
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(8, 1));  // unmapped
  CHECK(client.exception() == 0x02);
  CHECK(client.input(38, 1).empty());
  CHECK(client.exception() == 0x02);

  // Nothing failed on the wire, and the Rieker unit is still served.
  CHECK((client.input(6, 1).at(0) & 0x04) == 0);
  client.unit(kRiekerUnit);
  CHECK(client.input(0, 2).size() == 2);
}

TEST_CASE("a Dyna re-addressed through the gateway is followed, and a reset re-reads it") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  CHECK(client.write(7, 42));
  CHECK(plant.modbus_sim->call([](DynaSimulator& s) { return s.sensor(0).address(); }) == 42);
  CHECK(client.input(14, 1) == std::vector<std::uint16_t>{42});
  CHECK(client.holding(7, 1) == std::vector<std::uint16_t>{42});  // EEPROM 16, read back
  CHECK(client.write(5, 1));  // reset
  CHECK(plant.modbus_sim->call([](DynaSimulator& s) { return s.sensor(0).resets(); }) == 1);
  CHECK(plant.wait_online(kModbusDynaUnit));  // identity read again, at the new address
  const auto words = client.input(0, 28);
  REQUIRE(words.size() == 28);
  CHECK(string_at(words, 16, 10) == "4242      ");
  const auto raw = client.input(100, 2);
  REQUIRE(raw.size() == 2);
  CHECK(std::int32_t(std::uint32_t(raw[0]) << 16 | raw[1]) == 1001);
}
