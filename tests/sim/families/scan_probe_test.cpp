// Each family's scan probe (driver/scan.h) over a pseudo-terminal against its simulator: a
// sensor that answers, an address nobody has, and two sensors at one address, whose replies
// collide and arrive garbled.
#include <doctest/doctest.h>

#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/scan_probe.h"
#include "modbus_rtu/simulator/simulator.h"
#include "rieker/scan_probe.h"
#include "rieker/simulator.h"
#include "sim/support/driver_bench.h"
#include "sim/support/dyna_bench.h"
#include "spectron/scan_probe.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using test::run_coroutine;

namespace {

ProbeSetup probe_at(std::uint32_t address) {
  ProbeSetup setup;
  setup.address = address;
  setup.timeout = 100ms;  // generous: the machine may be busy
  return setup;
}

rieker::SimulatedSensorOptions h6_at(std::uint16_t address) {
  rieker::SimulatedSensorOptions s;
  s.address = address;
  return s;
}

struct RiekerBench : test::DriverBench<rieker::RiekerSimulator> {
  explicit RiekerBench(std::vector<rieker::SimulatedSensorOptions> sensors)
      : DriverBench(options(std::move(sensors)), SerialLineOptions{}) {}
  static rieker::RiekerSimulatorOptions options(std::vector<rieker::SimulatedSensorOptions> s) {
    rieker::RiekerSimulatorOptions o;
    o.sensors = std::move(s);
    return o;
  }
  ProbeResult probe(ProbeFunction function, std::uint32_t address) {
    return run_coroutine(io, function(*line, probe_at(address)));
  }
};

}  // namespace

TEST_CASE("Rieker Check Address finds the sensor there, silence elsewhere, a collision at a shared address") {
  RiekerBench bench({h6_at(7), h6_at(5), h6_at(5)});
  const ProbeResult seven = bench.probe(rieker::check_address_probe, 7);
  CHECK(seven.outcome == ProbeOutcome::answered);
  CHECK(seven.address == 7u);
  CHECK(bench.probe(rieker::check_address_probe, 6).outcome == ProbeOutcome::silent);
  const ProbeResult five = bench.probe(rieker::check_address_probe, 5);
  CHECK(five.outcome == ProbeOutcome::garbled);
  CHECK(bench.sim->counters().collisions == 1);
  // The collision did not spill over: the next address is probed cleanly.
  CHECK(bench.probe(rieker::check_address_probe, 7).outcome == ProbeOutcome::answered);
}

TEST_CASE("Rieker broadcast Get Address gives the one sensor's address, with two they collide") {
  RiekerBench one({h6_at(4242)});
  const ProbeResult found = one.probe(rieker::broadcast_get_address_probe, 0);
  CHECK(found.outcome == ProbeOutcome::answered);
  CHECK(found.address == 4242u);

  RiekerBench two({h6_at(1), h6_at(2)});
  CHECK(two.probe(rieker::broadcast_get_address_probe, 0).outcome == ProbeOutcome::garbled);
}

TEST_CASE_TEMPLATE("Dyna Read Sensor finds a module, silence elsewhere, a collision at a shared address",
                   P, test::NineBit, test::ModbusAscii) {
  test::Bench bench(P::protocol, {test::dyna(3), test::dyna(9), test::dyna(9)});
  const ProbeFunction probe = P::protocol == spectron::Protocol::nine_bit
                                  ? spectron::nine_bit_read_sensor_probe
                                  : spectron::ascii_read_sensor_probe;
  const ProbeResult three = run_coroutine(bench.io, probe(*bench.line, probe_at(3)));
  CHECK(three.outcome == ProbeOutcome::answered);
  CHECK(three.address == 3u);
  CHECK(run_coroutine(bench.io, probe(*bench.line, probe_at(4))).outcome == ProbeOutcome::silent);
  CHECK(run_coroutine(bench.io, probe(*bench.line, probe_at(9))).outcome == ProbeOutcome::garbled);
  CHECK(bench.sim->counters().collisions == 1);
}

TEST_CASE("Modbus RTU FC 17 finds a device by its exception reply, a shared address collides") {
  modbus_rtu::RtuSimulatorOptions options;
  for (const std::uint8_t slave : {1, 3, 3, 4})
    options.devices.push_back(modbus_rtu::rtu_inclinometer(slave));
  // Slave 1 has no FC 17, as many devices: its "illegal function" shows it is there. Slave 4
  // answers it, as the preset does.
  options.devices.front().set_identification({});
  SerialLineOptions line;
  line.framing = Framing::eight_even_one;
  line.baud = 19200;
  test::DriverBench<modbus_rtu::RtuSimulator> bench(std::move(options), line);
  const ProbeResult one = run_coroutine(bench.io, modbus_rtu::device_probe(*bench.line, probe_at(1)));
  CHECK(one.outcome == ProbeOutcome::answered);
  CHECK(one.detail.find("exception 1") == 0);
  const ProbeResult four = run_coroutine(bench.io, modbus_rtu::device_probe(*bench.line, probe_at(4)));
  CHECK(four.outcome == ProbeOutcome::answered);
  CHECK(four.detail.empty());
  CHECK(run_coroutine(bench.io, modbus_rtu::device_probe(*bench.line, probe_at(2))).outcome ==
        ProbeOutcome::silent);
  CHECK(run_coroutine(bench.io, modbus_rtu::device_probe(*bench.line, probe_at(3))).outcome ==
        ProbeOutcome::garbled);
  CHECK(bench.sim->counters().collisions == 1);
}
