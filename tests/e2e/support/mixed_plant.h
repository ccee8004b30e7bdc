// A mixed plant for end-to-end tests, in one gateway process: a Rieker H6 (unit 1, address
// 223) and an H4360 (unit 2, address 224) on a Rieker bus, a Dyna on a Modbus-ASCII bus
// (unit 4, module 1, serial 4242) and a Dyna on a 9-bit bus (unit 5, module 0, serial 4343,
// eeprom_reserved_writes on), each bus a simulator on its own pseudo-terminal; writes on.
#pragma once

#include <chrono>
#include <cstdint>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"
#include "spectron/simulator.h"

namespace tiltgate::test {

using namespace std::chrono_literals;
using spectron::DynaSimulator;

inline constexpr int kRiekerUnit = 1;
inline constexpr int kH4360Unit = 2;
inline constexpr int kModbusDynaUnit = 4;   // module 1 on the Modbus-ASCII bus
inline constexpr int kNineBitDynaUnit = 5;  // module 0 (the factory address) on the 9-bit bus

inline float float_at(const std::vector<std::uint16_t>& words, std::size_t at) {
  return modbus_get_float_abcd(words.data() + at);
}

inline std::string string_at(const std::vector<std::uint16_t>& words, std::size_t at, std::size_t chars) {
  std::string text;
  for (std::size_t i = 0; i < chars; ++i) {
    const std::uint16_t w = words[at + i / 2];
    text += char(i % 2 == 0 ? w >> 8 : w & 0xFF);
  }
  return text;
}

inline spectron::DynaSimulatorOptions dyna_bus(spectron::Protocol protocol, std::uint8_t address,
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
    rieker::SimulatedSensorOptions h4360;
    h4360.model = rieker::Model::h4360;
    h4360.address = 224;
    h4360.angle_x = -30.5;
    rieker::RiekerSimulatorOptions rieker_options;
    rieker_options.sensors = {h6, h4360};
    rieker_options.link_path = (dir.path() / "ttyRieker").string();
    rieker_sim = std::make_unique<SimulatorThread>(rieker_options);
    const auto modbus_link = (dir.path() / "ttyDynaModbus").string();
    modbus_sim = std::make_unique<DynaSimulatorThread>(
        dyna_bus(spectron::Protocol::modbus_ascii, 1, 4242, modbus_link));
    const auto nine_bit_link = (dir.path() / "ttyDyna9bit").string();
    nine_bit_sim = std::make_unique<DynaSimulatorThread>(
        dyna_bus(spectron::Protocol::nine_bit, 0, 4343, nine_bit_link));
    const std::string_view retry = "timeout_ms = 100\nretries = 1";
    const auto config = dir.write(
        "mixed.toml",
        server_table(port, "writes = true") +
            bus_table("rieker-line", rieker_options.link_path, fmt::format("protocol = \"rieker\"\n{}", retry)) +
            bus_table("dyna-modbus", modbus_link,
                      fmt::format("protocol = \"spectron-modbus\"\nbaud = 28800\n{}", retry)) +
            bus_table("dyna-9bit", nine_bit_link,
                      fmt::format("protocol = \"spectron-9bit\"\nbaud = 28800\n{}", retry)) +
            sensor_table("boom", "rieker-line", "h6", 223, kRiekerUnit, "poll_ms = 50") +
            sensor_table("luffing", "rieker-line", "h4360", 224, kH4360Unit, "poll_ms = 50") +
            sensor_table("slewing-ring", "dyna-modbus", "dyna", 1, kModbusDynaUnit,
                         "poll_ms = 50\ncounts_per_degree = 100\nzero_counts = 1") +
            sensor_table("jib", "dyna-9bit", "dyna", 0, kNineBitDynaUnit,
                         "poll_ms = 50\ncounts_per_degree = 200.0\neeprom_reserved_writes = true"));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"--log-level", "debug", "run", "--config", config.string()},
        dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
    for (int unit : {kRiekerUnit, kH4360Unit, kModbusDynaUnit, kNineBitDynaUnit}) {
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
inline bool wait_input(ModbusClient& client, int address, const std::vector<std::uint16_t>& expected) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (client.input(address, int(expected.size())) == expected) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

inline std::uint16_t eeprom(DynaSimulatorThread& sim, int location) {
  return sim.call([&](DynaSimulator& s) { return s.sensor(0).eeprom(location).value_or(0); });
}

}  // namespace tiltgate::test
