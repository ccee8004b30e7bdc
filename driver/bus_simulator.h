// A family's simulated bus, as `tiltgate sim FAMILY`, `tiltgate demo` and the tests run it: a
// pseudo-terminal the gateway opens as if it were an RS485 adapter (driver/family.h).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <span>
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
  std::string protocol;         // one of SimulatorDescriptor::protocols, when it has any
  std::string link;             // optional stable symlink to the pty
  std::uint32_t pace_baud = 0;  // 0: answer at once; else pace replies at this baud rate
  // 0: hear requests at any rate; else only those sent at this baud rate (PtyBusServerOptions).
  std::uint32_t listen_baud = 0;
  // Sensors may share an address, as on a bus commissioned by mistake: their replies collide.
  bool shared_addresses = false;
  // The demo: angles move slowly, so a status page shows every sensor alive. Families whose
  // simulators always sway ignore it; tests leave it off to read exact values.
  bool sway = false;
};

struct SimulatorDescriptor {
  std::string_view command;          // `tiltgate sim COMMAND`
  std::string_view help;             // the subcommand's one-line help
  std::string_view default_sensors;  // --sensors when not given
  std::string_view sensors_help;
  // --protocol choices, the default first; none: the family's simulator has one protocol.
  std::span<const std::string_view> protocols;
  std::string_view protocols_help;
  // A simulator serving `setup`, not started; the error is about --sensors.
  Expected<std::unique_ptr<BusSimulator>, std::string> (*make)(boost::asio::io_context& io,
                                                               const SimulatorSetup& setup);
};

// A file one of the family's own [[sensor]] keys names (a device profile, ...), for a demo
// sensor: the demo writes `contents` into a private folder it removes at exit, and the family
// reads `key` as naming that file, as it would from a configuration.
struct DemoFile {
  std::string_view key;        // one of FamilyDescriptor::sensor_keys
  std::string_view file_name;  // a plain file name
  std::string_view contents;
};

// One sensor of the family's part of `tiltgate demo`. Its family's keys other than `files`
// take their defaults.
struct DemoSensor {
  std::string_view name;
  std::string_view model;
  std::uint32_t address = 0;
  std::span<const DemoFile> files = {};
};

// The family's part of `tiltgate demo`: one bus of simulated sensors.
struct DemoBus {
  std::string_view bus_name;
  std::string_view protocol;  // a ProtocolDescriptor name
  std::uint32_t baud = 0;     // the bus's rate; the simulator paces replies at it
  SimulatorSetup simulator;   // what the family's simulator serves (sensors, protocol)
  std::span<const DemoSensor> sensors;
  // mbpoll examples for the demo's help, with {host}, {port} and {unit} (the bus's first
  // sensor's unit id) to fill in.
  std::span<const std::string_view> examples;
};

}  // namespace tiltgate
