// A virtual Rieker RS485 bus on a pseudo-terminal: the gateway (or a test) opens slave_path()
// (or the stable link path) as if it were a USB-RS485 adapter, and the simulated sensors on
// the bus answer its requests. Used by the sim tests, the demo and `tiltgate sim rieker`.
//
// Threading: the simulator runs on the caller's io_context, which must outlive it. Call its
// methods from the thread running that io_context (or through post()), or while it is not
// running.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "rieker/frame_parser.h"
#include "rieker/simulated_sensor.h"
#include "serial/pty_bus_server.h"

namespace tiltgate::rieker {

struct RiekerSimulatorOptions {
  std::vector<SimulatedSensorOptions> sensors;
  // Pace replies as a real line at this baud would: each waits bytes * 10 / baud seconds
  // (8N1: 10 bits a byte). Off by default so tests run fast.
  std::optional<std::uint32_t> pace_baud;
  // Answer only requests sent at this baud rate (PtyBusServerOptions::listen_baud).
  std::optional<std::uint32_t> listen_baud;
  // Time a sensor takes to start answering ("as fast as possible").
  std::chrono::microseconds reply_latency{200};
  // A stable path re-pointed (atomically) at the current slave on every (re)open and removed
  // on unplug, since a new pseudo-terminal gets a new /dev/pts number. Empty: no link.
  std::string link_path;
  // Sensors answer a frame addressed to them that fails its CRC with NAK 0.
  bool nak_on_crc_failure = true;
};

struct SimulatorCounters {
  std::uint64_t requests_seen = 0;   // frames with a good CRC, whoever they were for
  std::uint64_t replies_sent = 0;
  std::uint64_t crc_errors = 0;      // as RiekerFrameParser counts them, over every (re)open
  std::uint64_t bytes_received = 0;
  std::uint64_t collisions = 0;      // requests more than one sensor answered (sent garbled)
};

class RiekerSimulator {
 public:
  RiekerSimulator(boost::asio::io_context& io, RiekerSimulatorOptions options);
  ~RiekerSimulator();
  RiekerSimulator(const RiekerSimulator&) = delete;
  RiekerSimulator& operator=(const RiekerSimulator&) = delete;

  // Opens a pseudo-terminal (and the link) and starts serving it.
  Expected<Done, std::string> start();
  // Closes the pseudo-terminal and removes the link: the gateway's next read or write on the
  // slave fails as on an unplugged adapter. The sensors keep their state (the bus stays powered).
  void unplug() { server_.unplug(); }
  // A new pseudo-terminal (a new slave path; the link follows it).
  Expected<Done, std::string> replug() { return start(); }
  // Stops serving for good; the destructor does it too.
  void stop() { unplug(); }

  bool plugged() const { return server_.plugged(); }
  // The current slave path; empty while unplugged.
  const std::string& slave_path() const { return server_.slave_path(); }
  const std::string& link_path() const { return server_.link_path(); }

  std::size_t sensor_count() const { return sensors_.size(); }
  SimulatedSensor& sensor(std::size_t index) { return sensors_.at(index); }
  // The sensor now at `address` (it follows Set Address), or nullptr.
  SimulatedSensor* sensor_by_address(std::uint16_t address);

  const SimulatorCounters& counters() const { return counters_; }

 private:
  void on_bytes(std::span<const std::uint8_t> bytes);
  void dispatch(const Frame& request);
  // A late sensor's reply waits `extra_delay` more; later replies queue behind it, as on a bus
  // where the master waits for a late sensor before anyone else talks.
  void queue_reply(std::vector<std::uint8_t> bytes,
                   std::chrono::milliseconds extra_delay = std::chrono::milliseconds{0});
  SimTime now() const;

  RiekerSimulatorOptions options_;
  std::vector<SimulatedSensor> sensors_;
  std::chrono::steady_clock::time_point started_;
  RiekerFrameParser parser_;  // a fresh one for every (re)open, as a new adapter would see
  SimulatorCounters counters_;
  PtyBusServer server_;  // last: destroyed (and unplugged) before what its callbacks use
};

}  // namespace tiltgate::rieker
