// A family's simulated bus, as `tiltgate sim FAMILY`, `tiltgate demo` and the tests run it: a
// pseudo-terminal the gateway opens as if it were an RS485 adapter (driver/family_commands.h).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

class BusSimulator {
 public:
  virtual ~BusSimulator() = default;
  // Opens the pseudo-terminal (and the link) and starts serving it.
  virtual Expected<Done, std::string> start() = 0;
  virtual void stop() = 0;
  virtual const std::string& slave_path() const = 0;
  virtual std::size_t sensor_count() const = 0;
  // What it simulates, for the log: "sensor(s)" of the family.
  virtual std::string what() const = 0;
  // One line of `tiltgate sim FAMILY`'s standard input while it runs (e.g. "angle 1 12.5 -3"):
  // changes a simulated sensor, so a benchmark or an engineer can see how soon the change
  // reaches Modbus. The error says what is wrong with the line. Families without such
  // commands keep this default.
  virtual Expected<Done, std::string> command(std::string_view line) {
    (void)line;
    return Unexpected{what() + " take no commands"};
  }
};

// The options of `tiltgate sim FAMILY`.
struct SimulatorSetup {
  std::string sensors;          // the family's --sensors list, e.g. model:address[,...]
  std::string protocol;         // a ProtocolDescriptor name of the family; empty: its first
  std::string link;             // optional stable symlink to the pty
  std::uint32_t pace_baud = 0;  // 0: answer at once; else pace replies at this baud rate
  // 0: hear requests at any rate; else only those sent at this baud rate (PtyBusServerOptions).
  std::uint32_t listen_baud = 0;
  // Sensors may share an address, as on a bus commissioned by mistake: their replies collide.
  bool shared_addresses = false;
  // A second master port on the same line, with this stable symlink (a warm-standby pair's
  // other gateway); empty: one master.
  std::string second_master{};
  // A file the line's counters are rewritten to while it runs (serial/simulated_line_stats.h);
  // empty: none.
  std::string stats{};
  // The demo: angles move slowly, so a status page shows every sensor alive. Families whose
  // simulators always sway ignore it; tests leave it off to read exact values.
  bool sway = false;
};

}  // namespace tiltgate
