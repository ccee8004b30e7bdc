// build/tiltgate run with a mixed plant in one process: a Rieker H6 on a Rieker bus, a Dyna on
// a Modbus-ASCII bus and a Dyna on a 9-bit bus, each bus a simulator on its own pseudo-terminal,
// read and written with the real libmodbus client.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/simulator_thread.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "rieker/simulator.h"
#include "spectron/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using spectron::DynaSimulator;

namespace {

constexpr int kRiekerUnit = 1;
constexpr int kModbusDynaUnit = 4;   // module 1 on the Modbus-ASCII bus
constexpr int kNineBitDynaUnit = 5;  // module 0 (the factory address) on the 9-bit bus

float float_at(const std::vector<std::uint16_t>& words, std::size_t at) {
  return modbus_get_float_abcd(words.data() + at);
}

std::string string_at(const std::vector<std::uint16_t>& words, std::size_t at, std::size_t chars) {
  std::string text;
  for (std::size_t i = 0; i < chars; ++i) {
    const std::uint16_t w = words[at + i / 2];
    text += char(i % 2 == 0 ? w >> 8 : w & 0xFF);
  }
  return text;
}

spectron::DynaSimulatorOptions dyna_bus(spectron::Protocol protocol, std::uint8_t address,
                                        std::uint16_t serial, const std::string& link) {
  spectron::SimulatedDynaOptions module;
  module.address = address;
  module.serial = serial;
  module.counts = 1001;
  module.temperature = -40;
  module.firmware = "V1.07";  // the 9-bit "F" reply; Modbus-ASCII reports the word 0x0107
  spectron::DynaSimulatorOptions options;
  options.protocol = protocol;
  options.sensors = {module};
  options.link_path = link;
  return options;
}

// The three buses and the gateway serving them on a free loopback port, writes enabled.
struct MixedPlant {
  MixedPlant() {
    rieker::SimulatedSensorOptions h6;
    h6.model = rieker::Model::h6;
    h6.address = 223;
    h6.angle_x = 1.5;
    h6.angle_y = -2.25;
    h6.serial = "962285";
    rieker::RiekerSimulatorOptions rieker_options;
    rieker_options.sensors = {h6};
    rieker_options.link_path = (dir.path() / "ttyRieker").string();
    rieker_sim = std::make_unique<SimulatorThread>(rieker_options);
    const auto modbus_link = (dir.path() / "ttyDynaModbus").string();
    modbus_sim = std::make_unique<DynaSimulatorThread>(
        dyna_bus(spectron::Protocol::modbus_ascii, 1, 4242, modbus_link));
    const auto nine_bit_link = (dir.path() / "ttyDyna9bit").string();
    nine_bit_sim = std::make_unique<DynaSimulatorThread>(
        dyna_bus(spectron::Protocol::nine_bit, 0, 4343, nine_bit_link));
    const auto config = dir.write("mixed.toml", fmt::format(R"(
[server]
listen = "127.0.0.1"
port = {}
writes = true

[[bus]]
name = "rieker-line"
port = "{}"
protocol = "rieker"
timeout_ms = 100
retries = 1

[[bus]]
name = "dyna-modbus"
port = "{}"
protocol = "spectron-modbus"
baud = 28800
timeout_ms = 100
retries = 1

[[bus]]
name = "dyna-9bit"
port = "{}"
protocol = "spectron-9bit"
baud = 28800
timeout_ms = 100
retries = 1

[[sensor]]
name = "boom"
bus = "rieker-line"
model = "h6"
address = 223
unit_id = {}
poll_ms = 50

[[sensor]]
name = "slewing-ring"
bus = "dyna-modbus"
model = "dyna"
address = 1
unit_id = {}
poll_ms = 50
counts_per_degree = 100
zero_counts = 1

[[sensor]]
name = "jib"
bus = "dyna-9bit"
model = "dyna"
address = 0
unit_id = {}
poll_ms = 50
counts_per_degree = 200.0
)",
                                                            port, rieker_options.link_path,
                                                            modbus_link, nine_bit_link, kRiekerUnit,
                                                            kModbusDynaUnit, kNineBitDynaUnit));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"--log-level", "debug", "run", "--config", config.string()},
        dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
    for (int unit : {kRiekerUnit, kModbusDynaUnit, kNineBitDynaUnit}) {
      REQUIRE_MESSAGE(wait_online(unit), "unit ", unit, " not online: ", gateway->log());
    }
  }

  // Polls until the unit's angle is readable and its identity known (the first polls take a
  // moment).
  bool wait_online(int unit) {
    ModbusClient client(port, unit);
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto words = client.input(0, 7);
      if (!words.empty() && (words[6] & 0x09) == 0x01) return true;  // online, identity known
      std::this_thread::sleep_for(50ms);
    }
    return false;
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThread> rieker_sim;
  std::unique_ptr<DynaSimulatorThread> modbus_sim;
  std::unique_ptr<DynaSimulatorThread> nine_bit_sim;
  std::unique_ptr<GatewayProcess> gateway;
};

// Reads the input registers from `address` until they show `expected` (a write reaches the
// readings at the next poll).
bool wait_input(ModbusClient& client, int address, const std::vector<std::uint16_t>& expected) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (client.input(address, int(expected.size())) == expected) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

std::uint16_t eeprom(DynaSimulatorThread& sim, int location) {
  return sim.call([&](DynaSimulator& s) { return s.sensor(0).eeprom(location).value_or(0); });
}

}  // namespace

TEST_CASE("a Dyna on each Spectron bus and a Rieker H6 are served by one process") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  auto words = client.input(0, 28);
  REQUIRE(words.size() == 28);
  CHECK(float_at(words, 0) == 10.0f);                                   // (1001 - 1) / 100
  CHECK(std::int32_t(std::uint32_t(words[2]) << 16 | words[3]) == 1001);  // raw counts
  CHECK(std::int16_t(words[4]) == 1000);                                 // hundredths
  CHECK(std::int16_t(words[5]) == -40);                                  // raw temperature
  CHECK((words[6] & 0x0F) == 0x01);  // online, fresh, no failed write, identity known
  CHECK(words[12] == 65535);         // no NAK: the Dyna has none
  CHECK(words[13] == 65535);         // nor lock levels
  CHECK(words[14] == 1);             // module address
  CHECK(string_at(words, 16, 10) == "4242      ");
  CHECK(string_at(words, 21, 8) == "01.07   ");
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{1});

  client.unit(kNineBitDynaUnit);
  words = client.input(0, 28);
  REQUIRE(words.size() == 28);
  CHECK(float_at(words, 0) == doctest::Approx(5.005));  // 1001 / 200
  CHECK(std::int16_t(words[5]) == -40);
  CHECK(words[14] == 0);
  CHECK(string_at(words, 16, 10) == "4343      ");
  CHECK(string_at(words, 21, 8) == "V1.07   ");

  client.unit(kRiekerUnit);
  words = client.input(0, 4);
  REQUIRE(words.size() == 4);
  CHECK(float_at(words, 0) == 1.5f);
  CHECK(float_at(words, 2) == -2.25f);
}

TEST_CASE("Dyna writes: a named offset and the EEPROM window reach the module") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  CHECK(client.write(0, 1));  // sensor offset, EEPROM 6
  CHECK(eeprom(*plant.modbus_sim, 6) == 1);
  CHECK(wait_input(client, 2, {0, 1000}));  // raw counts: the module now subtracts it
  CHECK(client.holding(0, 1) == std::vector<std::uint16_t>{1});

  // The EEPROM window, location and value in one request: the PWM offset, EEPROM 20.
  CHECK(client.write(3, std::vector<std::uint16_t>{20, 355}));
  CHECK(eeprom(*plant.modbus_sim, 20) == 355);
  CHECK(client.holding(0, 5) == std::vector<std::uint16_t>{1, 0, 0, 20, 355});

  client.unit(kNineBitDynaUnit);  // the same through 9-bit addressing
  CHECK(client.write(2, 2501));   // PWM offset, EEPROM 20
  CHECK(eeprom(*plant.nine_bit_sim, 20) == 2501);
  CHECK(client.write(3, 10));  // the window: temperature offset, EEPROM 10
  CHECK(client.write(4, 5));
  CHECK(eeprom(*plant.nine_bit_sim, 10) == 5);
  CHECK(wait_input(client, 5, {std::uint16_t(-45)}));
}

TEST_CASE("Dyna writes the module cannot take are refused with 0x02 and 0x03") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  CHECK(client.write(3, 4));  // the serial number's location may be selected ...
  CHECK_FALSE(client.write(4, 1));
  CHECK(client.exception() == 0x03);  // ... but not written
  CHECK(eeprom(*plant.modbus_sim, 4) == 4242);
  CHECK(client.write(3, 100));  // reserved (the note's example location): read-only too
  CHECK_FALSE(client.write(4, 355));
  CHECK(client.exception() == 0x03);
  CHECK(eeprom(*plant.modbus_sim, 100) == 0);
  CHECK_FALSE(client.write(3, 5));  // odd
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(3, 24));  // not in the memory map
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(3, 300));  // beyond the register's range 2..280
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(6, 8));  // not one of the five baud codes
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(5, 2));  // the only command is 1
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(7, 251));  // Modbus-ASCII modules: 1..250
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(8, 1));  // unmapped
  CHECK(client.exception() == 0x02);
  CHECK(client.input(30, 1).empty());
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
  CHECK(client.write(5, 1));  // reset
  CHECK(plant.modbus_sim->call([](DynaSimulator& s) { return s.sensor(0).resets(); }) == 1);
  CHECK(plant.wait_online(kModbusDynaUnit));  // identity read again, at the new address
  const auto words = client.input(0, 28);
  REQUIRE(words.size() == 28);
  CHECK(std::int32_t(std::uint32_t(words[2]) << 16 | words[3]) == 1001);
  CHECK(string_at(words, 16, 10) == "4242      ");
}
