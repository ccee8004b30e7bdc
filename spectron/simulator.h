// A virtual Dyna RS485 bus on a pseudo-terminal: the gateway (or a test) opens slave_path()
// (or the stable link path) as if it were a USB-RS485 adapter, and the simulated modules on
// the bus answer its requests in the protocol chosen in the options. Used by the sim tests,
// the demo and `tiltgate sim spectron`.
//
// 9-bit addressing on a pseudo-terminal. A pty carries bytes, not parity bits, so the ninth
// bit that marks an address byte cannot reach the simulator. In nine_bit mode the simulator
// therefore uses a framing convention that exists ONLY in simulation:
//   the address byte is the first byte ever received, the first byte after a CR LF, or the
//   first byte after 20 ms of silence that followed part of a command body.
// (Silence right after an address byte does not restart framing: the serial line sends the
// address byte, drains it, switches parity, then sends the body, and on a busy machine that
// switch can take longer than 20 ms.) The real UART path (mark parity for the address byte,
// space parity for the body, in serial/serial_line) does not depend on this convention; it
// just happens to produce byte streams the convention splits correctly.
//
// Threading: the simulator runs on the caller's io_context, which must outlive it. Call its
// methods from the thread running that io_context (or through post()), or while it is not
// running.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "serial/pty_bus_server.h"
#include "spectron/ascii_codec.h"
#include "spectron/protocol.h"
#include "spectron/simulated_dyna.h"

namespace tiltgate::spectron {

// The silence after part of a 9-bit command body that makes the next byte an address byte.
inline constexpr std::chrono::milliseconds kNineBitResyncSilence{20};

struct DynaSimulatorOptions {
  Protocol protocol = Protocol::nine_bit;
  std::vector<SimulatedDynaOptions> sensors;
  // Pace replies as a real line at this baud would: each waits bytes * 11 / baud seconds
  // (8E1 and 9-bit framing both take 11 bits a byte). Off by default so tests run fast.
  std::optional<std::uint32_t> pace_baud;
  // Answer only requests sent at this baud rate (PtyBusServerOptions::listen_baud).
  std::optional<std::uint32_t> listen_baud;
  // Time a module takes to start answering.
  std::chrono::microseconds reply_latency{200};
  // A stable path re-pointed (atomically) at the current slave on every (re)open and removed
  // on unplug, since a new pseudo-terminal gets a new /dev/pts number. Empty: no link.
  std::string link_path;
};

struct DynaSimulatorCounters {
  std::uint64_t requests_seen = 0;  // well-formed requests, whoever they were for
  std::uint64_t replies_sent = 0;
  std::uint64_t lrc_errors = 0;     // Modbus-ASCII frames with a bad LRC (never answered)
  std::uint64_t malformed = 0;      // frames or 9-bit commands that could not be read
  std::uint64_t bytes_received = 0;
  std::uint64_t collisions = 0;     // requests more than one module answered (sent garbled)
};

class DynaSimulator {
 public:
  DynaSimulator(boost::asio::io_context& io, DynaSimulatorOptions options);
  ~DynaSimulator();
  DynaSimulator(const DynaSimulator&) = delete;
  DynaSimulator& operator=(const DynaSimulator&) = delete;

  // Opens a pseudo-terminal (and the link) and starts serving it.
  Expected<Done, std::string> start();
  // Closes the pseudo-terminal and removes the link: the gateway's next read or write on the
  // slave fails as on an unplugged adapter. The modules keep their state (the bus stays powered).
  void unplug() { server_.unplug(); }
  // A new pseudo-terminal (a new slave path; the link follows it).
  Expected<Done, std::string> replug() { return start(); }
  // Stops serving for good; the destructor does it too.
  void stop() { unplug(); }

  bool plugged() const { return server_.plugged(); }
  Protocol protocol() const { return options_.protocol; }
  // The current slave path; empty while unplugged.
  const std::string& slave_path() const { return server_.slave_path(); }
  const std::string& link_path() const { return server_.link_path(); }

  std::size_t sensor_count() const { return sensors_.size(); }
  SimulatedDyna& sensor(std::size_t index) { return sensors_.at(index); }
  // The module now at `address` (it follows writes to EEPROM location 16), or nullptr.
  SimulatedDyna* sensor_by_address(std::uint8_t address);

  const DynaSimulatorCounters& counters() const { return counters_; }

 private:
  struct Framing;  // the request framing of the current pseudo-terminal

  void on_bytes(std::span<const std::uint8_t> bytes);
  void on_nine_bit_bytes(std::span<const std::uint8_t> bytes);
  void on_ascii_bytes(std::span<const std::uint8_t> bytes);
  // The modules' replies to one request: the first, and how many answered.
  struct Replies {
    std::optional<std::vector<std::uint8_t>> first;
    std::chrono::milliseconds delay{0};
    std::size_t count = 0;
    void add(std::vector<std::uint8_t> bytes, std::chrono::milliseconds extra_delay) {
      if (count++ > 0) return;
      first = std::move(bytes);
      delay = extra_delay;
    }
  };
  void send(Replies replies);
  // A late module's reply waits `extra_delay` more; later replies queue behind it.
  void queue_reply(std::vector<std::uint8_t> bytes,
                   std::chrono::milliseconds extra_delay = std::chrono::milliseconds{0});
  SimTime now() const;

  DynaSimulatorOptions options_;
  std::vector<SimulatedDyna> sensors_;
  std::chrono::steady_clock::time_point started_;
  std::unique_ptr<Framing> framing_;  // a fresh one for every (re)open
  DynaSimulatorCounters counters_;
  PtyBusServer server_;  // last: destroyed (and unplugged) before what its callbacks use
};

}  // namespace tiltgate::spectron
