// A virtual Rieker RS485 bus on a pseudo-terminal: the gateway (or a test) opens slave_path()
// (or the stable link path) as if it were a USB-RS485 adapter, and the simulated sensors on
// the bus answer its requests. Used by the sim tests, the demo and `tiltgate sim rieker`.
// The pty, pacing, plugging and collisions are the simulated bus's (serial/simulated_bus.h).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "rieker/frame_parser.h"
#include "rieker/simulated_sensor.h"
#include "serial/simulated_bus.h"

namespace tiltgate::rieker {

struct RiekerSimulatorOptions : SimulatedBusOptions {
  std::vector<SimulatedSensorOptions> sensors;
  // Sensors answer a frame addressed to them that fails its CRC with NAK 0.
  bool nak_on_crc_failure = true;
};

struct SimulatorCounters : SimulatedBusCounters {
  std::uint64_t crc_errors = 0;  // as RiekerFrameParser counts them, over every (re)open
};

class RiekerSimulator final : public SimulatedBus {
 public:
  RiekerSimulator(boost::asio::io_context& io, RiekerSimulatorOptions options);

  std::size_t sensor_count() const override { return sensors_.size(); }
  std::string what() const override { return "Rieker sensor(s)"; }
  // "angle ADDRESS X [Y]": the sensor's raw angles in degrees, fixed from now on.
  // "silent ADDRESS": the sensor stops answering (unpowered, its drop cut); "garbage ADDRESS":
  // every reply's CRC broken; "late ADDRESS MS": every reply MS ms later; "busy ADDRESS": NAK 5
  // to every query; "answer ADDRESS" undoes them all.
  Expected<Done, std::string> command(std::string_view line) override;

  SimulatedSensor& sensor(std::size_t index) { return sensors_.at(index); }
  // The sensor now at `address` (it follows Set Address), or nullptr.
  SimulatedSensor* sensor_by_address(std::uint16_t address);

  SimulatorCounters counters() const;

 private:
  void receive(std::span<const std::uint8_t> bytes) override;
  void reset_framing() override { parser_ = RiekerFrameParser{}; }
  void dispatch(const Frame& request);

  RiekerSimulatorOptions options_;
  std::vector<SimulatedSensor> sensors_;
  RiekerFrameParser parser_;  // a fresh one for every (re)open, as a new adapter would see
  std::uint64_t crc_errors_ = 0;
};

}  // namespace tiltgate::rieker
