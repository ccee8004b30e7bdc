// The Dyna driver test bench: one Dyna bus on a pseudo-terminal at 28800 baud in either
// protocol's framing, simulated modules on it, and driver options to match.
#pragma once

#include <chrono>
#include <vector>

#include "sim/support/driver_bench.h"
#include "spectron/dyna_driver.h"
#include "spectron/simulator.h"

namespace tiltgate::test {

using namespace std::chrono_literals;
using spectron::DynaDriverOptions;
using spectron::DynaSimulator;
using spectron::DynaSimulatorOptions;
using spectron::Protocol;
using spectron::SimulatedDyna;
using spectron::SimulatedDynaOptions;

// The protocols every behaviour is checked in, with what each reports as firmware.
struct NineBit {
  static constexpr Protocol protocol = Protocol::nine_bit;
  static constexpr const char* firmware = "DYNA 1.07";  // the "F" reply, free text
};
struct ModbusAscii {
  static constexpr Protocol protocol = Protocol::modbus_ascii;
  static constexpr const char* firmware = "01.07";  // the 0x6A word 0x0107 (A7)
};

inline constexpr std::uint8_t kAddress = 7;  // valid on both buses

// One Dyna bus at 28800 baud in `protocol`'s framing with these modules.
struct Bench : DriverBench<DynaSimulator> {
  Bench(Protocol protocol, std::vector<SimulatedDynaOptions> sensors, int retries = 1)
      : DriverBench(simulator_options(protocol, std::move(sensors)),
                    line_options(protocol, retries)) {}

  static DynaSimulatorOptions simulator_options(Protocol protocol,
                                                std::vector<SimulatedDynaOptions> sensors) {
    DynaSimulatorOptions options;
    options.protocol = protocol;
    options.sensors = std::move(sensors);
    return options;
  }
  static SerialLineOptions line_options(Protocol protocol, int retries) {
    SerialLineOptions options;
    options.name = "dyna-line";
    options.baud = 28800;
    options.framing =
        protocol == Protocol::nine_bit ? Framing::nine_bit : Framing::eight_even_one;
    options.retries = retries;
    return options;
  }
  SimulatedDyna& module() { return sim->sensor(0); }
};

inline SimulatedDynaOptions dyna(std::uint8_t address = kAddress, std::int16_t counts = 1001) {
  SimulatedDynaOptions options;
  options.address = address;
  options.counts = counts;
  options.temperature = -40;
  return options;
}

inline DynaDriverOptions driver_for(Protocol protocol, int address = kAddress) {
  DynaDriverOptions options;
  options.name = "dyna";
  options.protocol = protocol;
  options.address = address;
  options.counts_per_degree = 100.0;
  options.zero_counts = 1.0;
  options.reset_settle = 20ms;
  options.reply_timeouts = kBenchReplyTimeouts;
  return options;
}

}  // namespace tiltgate::test
