// A virtual Modbus RTU bus on a pseudo-terminal: the gateway, a test or mbpoll opens
// slave_path() (or the stable link path) as if it were a USB-RS485 adapter, and the simulated
// slaves on it answer. Used by the sim tests and `tiltgate sim modbus-rtu`.
//
// Threading: the simulator runs on the caller's io_context, which must outlive it. Call its
// methods from the thread running that io_context (or through post()), or while it is not
// running.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "modbus_rtu/frame_parser.h"
#include "modbus_rtu/simulated_device.h"
#include "serial/pty_bus_server.h"

namespace tiltgate::modbus_rtu {

struct RtuSimulatorOptions {
  std::vector<SimulatedDevice> devices;
  // Pace replies as a real line at this baud would. Off by default so tests run fast.
  std::optional<std::uint32_t> pace_baud;
  // Answer only requests sent at this baud rate (PtyBusServerOptions::listen_baud).
  std::optional<std::uint32_t> listen_baud;
  unsigned bits_per_byte = 11;  // 8E1, the Modbus default (modbus_rtu/timing.h)
  // Time a slave takes to start answering.
  std::chrono::microseconds reply_latency{200};
  // A stable path re-pointed at the current slave on every (re)open. Empty: no link.
  std::string link_path;
  // Called for each device before it sees a request: lets a demo move its values.
  std::function<void(SimulatedDevice&)> before_request;
};

struct RtuSimulatorCounters {
  std::uint64_t requests_seen = 0;  // frames with a good CRC, whoever they were for
  std::uint64_t replies_sent = 0;
  std::uint64_t crc_errors = 0;     // as RtuFrameParser counts them, over every (re)open
  std::uint64_t bytes_received = 0;
  std::uint64_t collisions = 0;     // requests more than one device answered (sent garbled)
};

class RtuSimulator {
 public:
  RtuSimulator(boost::asio::io_context& io, RtuSimulatorOptions options);
  ~RtuSimulator();
  RtuSimulator(const RtuSimulator&) = delete;
  RtuSimulator& operator=(const RtuSimulator&) = delete;

  // Opens a pseudo-terminal (and the link) and starts serving it.
  Expected<Done, std::string> start();
  // Closes the pseudo-terminal: the gateway's next read or write fails as on an unplugged
  // adapter. The devices keep their registers.
  void unplug() { server_.unplug(); }
  Expected<Done, std::string> replug() { return start(); }
  void stop() { unplug(); }

  bool plugged() const { return server_.plugged(); }
  const std::string& slave_path() const { return server_.slave_path(); }
  const std::string& link_path() const { return server_.link_path(); }

  // The device at slave address `slave`, or nullptr.
  SimulatedDevice* device(std::uint8_t slave);
  const RtuSimulatorCounters& counters() const { return counters_; }

 private:
  void on_bytes(std::span<const std::uint8_t> bytes);

  RtuSimulatorOptions options_;
  RtuFrameParser parser_{FrameKind::request};  // a fresh one for every (re)open
  RtuSimulatorCounters counters_;
  PtyBusServer server_;  // last: destroyed (and unplugged) before what its callbacks use
};

}  // namespace tiltgate::modbus_rtu
