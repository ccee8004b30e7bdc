// A virtual Modbus RTU bus on a pseudo-terminal: the gateway, a test or mbpoll opens
// slave_path() (or the stable link path) as if it were a USB-RS485 adapter, and the simulated
// slaves on it answer. Used by the sim tests and `tiltgate sim modbus-rtu`.
//
// The pty, pacing, plugging and collisions are the simulated bus's (serial/simulated_bus.h).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "modbus_rtu/frame_parser.h"
#include "modbus_rtu/simulator/simulated_device.h"
#include "serial/simulated_bus.h"

namespace tiltgate::modbus_rtu {

struct RtuSimulatorOptions : SimulatedBusOptions {
  std::vector<SimulatedDevice> devices;
  unsigned bits_per_byte = 11;  // 8E1, the Modbus default (modbus_rtu/timing.h)
  // Called for each device before it sees a request: lets a demo move its values.
  std::function<void(SimulatedDevice&)> before_request;
};

struct RtuSimulatorCounters : SimulatedBusCounters {
  std::uint64_t crc_errors = 0;  // as RtuFrameParser counts them, over every (re)open
};

class RtuSimulator final : public SimulatedBus {
 public:
  RtuSimulator(boost::asio::io_context& io, RtuSimulatorOptions options);

  std::size_t sensor_count() const override { return options_.devices.size(); }
  std::string what() const override { return "Modbus RTU inclinometer(s)"; }

  // The device at slave address `slave`, or nullptr.
  SimulatedDevice* device(std::uint8_t slave);
  RtuSimulatorCounters counters() const;

 private:
  void receive(std::span<const std::uint8_t> bytes) override;
  void reset_framing() override { parser_ = RtuFrameParser{FrameKind::request}; }

  RtuSimulatorOptions options_;
  RtuFrameParser parser_{FrameKind::request};  // a fresh one for every (re)open
  std::uint64_t crc_errors_ = 0;
};

}  // namespace tiltgate::modbus_rtu
