// What every family's simulated bus shares (driver/bus_simulator.h): the pseudo-terminal it
// serves (PtyBusServer), pacing and the reply latency, plugging, the counters, and what happens
// when several simulated devices answer one request. A family's simulator builds on it with its
// own framing and devices: it reads the bytes the master sent (receive), starts its framing
// afresh on every (re)open and after noise on the line (reset_framing), and sends what its
// devices answered. A second master (a warm-standby pair's other gateway) may share the line,
// and the line's counters may be rewritten to a file as it runs (serial/simulated_line_stats.h).
//
// Threading: the bus runs on the caller's io_context, which must outlive it. Call its methods
// from the thread running that io_context (or through post()), or while it is not running.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/bus_simulator.h"
#include "driver/expected.h"
#include "driver/simulator_command.h"
#include "serial/pty_bus_server.h"
#include "serial/simulated_line_stats.h"

namespace tiltgate {

struct SimulatedBusOptions {
  // Pace replies as a real line at this baud would: each waits bytes * bits per byte / baud
  // seconds. Off by default so tests run fast.
  std::optional<std::uint32_t> pace_baud;
  // Answer only requests sent at this baud rate (PtyBusServerOptions::listen_baud).
  std::optional<std::uint32_t> listen_baud;
  // Time a device takes to start answering ("as fast as possible").
  std::chrono::microseconds reply_latency{200};
  // A stable path re-pointed (atomically) at the current slave on every (re)open and removed
  // on unplug, since a new pseudo-terminal gets a new /dev/pts number. Empty: no link.
  std::string link_path;
  // A second master on the line: its link path, empty for none (PtyBusServerOptions).
  std::optional<std::string> second_master_link = std::nullopt;
  // The line's counters rewritten to this file while it runs (serial/simulated_line_stats.h).
  // Empty: none.
  std::string stats_path{};
};

// The options every family's simulator takes from `tiltgate sim` and the demo: the link, the
// pacing, the listening rate (0 in the setup: off), a second master and the stats file.
void use_setup(const SimulatorSetup& setup, SimulatedBusOptions& options);

struct SimulatedBusCounters {
  std::uint64_t requests_seen = 0;   // well-formed requests, whoever they were for
  std::uint64_t replies_sent = 0;
  std::uint64_t bytes_received = 0;
  std::uint64_t collisions = 0;      // requests more than one device answered (sent garbled)
};

class SimulatedBus : public BusSimulator {
 public:
  ~SimulatedBus() override;
  SimulatedBus(const SimulatedBus&) = delete;
  SimulatedBus& operator=(const SimulatedBus&) = delete;

  // Opens every master's pseudo-terminal (and link) and starts serving them, and starts the
  // stats file.
  Expected<Done, std::string> start() final;
  // Closes a master's pseudo-terminal (the first's by default) and removes its link: that
  // gateway's next read or write on the slave fails as on an unplugged adapter. The devices
  // keep their state (the bus stays powered).
  void unplug(std::size_t master = 0) { server_.unplug(master); }
  // A new pseudo-terminal for a master (a new slave path; the link follows it).
  Expected<Done, std::string> replug(std::size_t master = 0);
  // The console's `unplug N` and `replug N` (N: 1 the --link master, 2 the --second-master
  // one): that master's adapter pulled out, or put back. None: the line is no such command.
  std::optional<Expected<Done, std::string>> plug_command(const SimulatorCommand& command);
  // Stops serving for good, with a last write of the stats file; the destructor does it too.
  void stop() final;

  bool plugged(std::size_t master = 0) const { return server_.plugged(master); }
  // The current slave path; empty while unplugged.
  const std::string& slave_path() const final { return server_.slave_path(); }
  const std::string& slave_path(std::size_t master) const { return server_.slave_path(master); }
  const std::string& link_path(std::size_t master = 0) const { return server_.link_path(master); }
  // What the stats file says.
  SimulatedLineStats line_stats() const;

 protected:
  // `bits_per_byte`: on the wire, for pacing (10 for 8N1; 11 for 8E1 and 9-bit framing).
  SimulatedBus(boost::asio::io_context& io, const SimulatedBusOptions& options,
               unsigned bits_per_byte);

  // Bytes as read from the master side: any split of what it wrote.
  virtual void receive(std::span<const std::uint8_t> bytes) = 0;
  // A new pseudo-terminal, or noise from masters that collided: the framing starts afresh, as
  // a new adapter would see (and a device that heard noise drops the frame it was reading).
  virtual void reset_framing() = 0;
  // A reply as the master receives it when two devices drive the bus at once: this default
  // breaks its checksum (the last byte flipped).
  virtual void garble(std::vector<std::uint8_t>& reply) const;

  // What the devices answered to one request: the first, and how many answered.
  class Answers {
   public:
    // `delay`: how much later than the usual latency the device answers.
    void add(std::vector<std::uint8_t> bytes, std::chrono::milliseconds delay);

   private:
    friend class SimulatedBus;
    std::optional<std::vector<std::uint8_t>> first_;
    std::chrono::milliseconds delay_{0};
    std::size_t count_ = 0;
  };

  void count_request() { ++counters_.requests_seen; }
  // Sends the first answer, if any. Devices that answer one request together drive the bus at
  // once: the master receives one reply, garbled; the first stands for it.
  void send(Answers answers);
  // A late device's reply waits `extra_delay` more; it does not hold up the replies of others,
  // and collides with one that would be on the line at the same time (serial/pty_bus_server.h).
  void send_reply(std::vector<std::uint8_t> bytes,
                  std::chrono::milliseconds extra_delay = std::chrono::milliseconds{0});

  // The counters, with those of a family's own (a struct deriving SimulatedBusCounters).
  template <class Counters>
  Counters with_bus_counters(Counters own) const {
    static_cast<SimulatedBusCounters&>(own) = counters_;
    return own;
  }
  // Since the bus was made: the simulated devices' clock.
  std::chrono::duration<double> elapsed() const {
    return std::chrono::steady_clock::now() - made_;
  }

 private:
  std::chrono::microseconds reply_latency_;
  std::chrono::steady_clock::time_point made_;
  SimulatedBusCounters counters_;
  std::optional<SimulatedLineStatsFile> stats_file_;
  PtyBusServer server_;
};

}  // namespace tiltgate
