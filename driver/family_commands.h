// A sensor family as the command line shows and runs it: the title its help texts name, the
// simulator of `tiltgate sim`, its bus in `tiltgate demo`, the words `tiltgate set` turns into
// its settings and the requests `tiltgate raw` builds. Each family folder fills in one
// FamilyCommands next to its FamilyDescriptor (driver/family.h), which it refers to; the
// gateway itself (config/, mapping/, gateway/) never sees these.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/bus_simulator.h"
#include "driver/expected.h"
#include "driver/family.h"
#include "driver/line.h"
#include "driver/sensor_driver.h"

namespace tiltgate {

// `tiltgate sim COMMAND`: its --protocol choices are the family's protocols' short names
// (ProtocolDescriptor::short_name), offered when it has more than one.
struct SimulatorDescriptor {
  std::string_view command;          // `tiltgate sim COMMAND`
  std::string_view help;             // the subcommand's one-line help
  std::string_view default_sensors;  // --sensors when not given
  std::string_view sensors_help;
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

// One sensor of the family's part of `tiltgate demo`, which its simulator serves as
// "model:address". Its family's keys other than `files` take their defaults.
struct DemoSensor {
  std::string_view name;
  std::string_view model;
  std::uint32_t address = 0;
  std::span<const DemoFile> files = {};
};

// The family's part of `tiltgate demo`: one bus of simulated sensors.
struct DemoBus {
  std::string_view bus_name;
  std::string_view protocol;  // a ProtocolDescriptor name; the simulator speaks it too
  std::uint32_t baud = 0;     // the bus's rate; the simulator paces replies at it
  std::span<const DemoSensor> sensors;
  // mbpoll examples for the demo's help, with {host}, {port} and {unit} (the bus's first
  // sensor's unit id) to fill in.
  std::span<const std::string_view> examples;
  // Sensors the simulated line has but the demo's configuration leaves out: fitted, not yet
  // configured, for a scan in the console to find and add (docs/web-console.md, "Try it").
  std::span<const DemoSensor> spare = {};
};

// A setting `tiltgate set` writes as several of a model's settings in order, one value each:
// `tiltgate set NAME V1 V2 ...` writes parts[0] := V1, then parts[1] := V2. Offered on the
// models that have every part among their settings.
struct CompoundSetting {
  std::string_view name;
  std::span<const std::string_view> parts;  // SettingDescriptor names, in write order
  std::string_view values;                  // the values' names for the usage: "LOCATION VALUE"
};

// What `tiltgate set` asks a family to turn the engineer's words into its own settings' values.
struct SetDescriptor {
  // The value of the models' baud_code setting that sets a sensor to `baud`, one of the
  // protocol's rates; none when the family's sensors cannot be set to it.
  std::optional<std::int64_t> (*baud_code)(std::int64_t baud);
  // The value of the models' command setting that carries out `command`; none when the
  // family's sensors have no such command.
  std::optional<double> (*command_value)(SensorCommand command);
  std::span<const CompoundSetting> compound_settings;
};

// `tiltgate raw`: one request of a family's protocol built from a function number and data
// bytes as the engineer gives them (the vendor tools' command section), and its reply decoded as
// far as the family's codec can.
struct RawSetup {
  std::string_view protocol;  // a ProtocolDescriptor name of the family
  std::uint32_t address = 0;  // the sensor's bus address
  std::uint32_t master_address = 0;
  std::int64_t function = 0;  // what it means on each protocol: RawDescriptor::function_help
  std::vector<std::uint8_t> data;
};

// What a reply says: `refused` for a NAK or an exception, with its meaning in `text`.
struct RawReply {
  bool refused = false;
  std::string text;  // one or more "name: value" lines, without a trailing newline
};

// One raw request and its reply: a family's exchange gives the bytes and its framer, and decodes
// what the framer accepted.
class RawExchange {
 public:
  virtual ~RawExchange() = default;
  // The request as the Line sends it; its framer belongs to this exchange.
  LineRequest request();
  // What the reply the framer accepted says.
  virtual RawReply decode() const = 0;

 protected:
  // `address_bytes`: how many leading bytes go with the 9th bit set (LineRequest).
  explicit RawExchange(std::vector<std::uint8_t> bytes, std::size_t address_bytes = 0)
      : bytes_(std::move(bytes)), address_bytes_(address_bytes) {}

 private:
  virtual ReplyFramer& framer() = 0;

  std::vector<std::uint8_t> bytes_;
  std::size_t address_bytes_;
};

// What one protocol takes as --function and --data.
struct RawLimits {
  std::string_view function_kind;  // "command code", "Modbus function code"
  std::int64_t first_function = 0;
  std::int64_t last_function = 0;
  std::size_t max_data = 0;  // data bytes a request carries at most
};

// A usage error when the setup's function or data are outside the limits.
Expected<Done, std::string> check_raw_setup(const RawSetup& setup, const RawLimits& limits);

struct RawDescriptor {
  // What --function and --data mean on the family's protocols, for the command's help.
  std::string_view function_help;
  // The exchange, or why the function or data cannot be sent (a usage error: the family
  // checks them with check_raw_setup and its protocol's limits).
  Expected<std::unique_ptr<RawExchange>, std::string> (*make)(const RawSetup& setup) = nullptr;
};

// `tiltgate info` on a sensor without its driver (a family whose driver needs a file the
// command line left out, commission/commission_options.h): what the device says of itself,
// asked with its protocol's own requests.
struct SelfReport {
  bool answered = false;  // the device replied to at least one request (a refusal included)
  bool identified = false;  // ... and told something of itself
  std::string text;       // "name: value" lines, each ending in a newline
};

struct IdentifyDescriptor {
  // `protocol`: the bus's, a ProtocolDescriptor name of the family (its framing may differ).
  boost::asio::awaitable<SelfReport> (*ask)(Line& line, std::string_view protocol,
                                            std::uint32_t address) = nullptr;
};

struct FamilyCommands {
  const FamilyDescriptor* family = nullptr;  // the family as the gateway runs it
  std::string_view title;  // for the command line's help: "Vendor Product"
  SimulatorDescriptor simulator;
  DemoBus demo;
  // `tiltgate set`: baud codes, commands and the settings written together. Every family fills
  // it in; a family without it (a test's) offers only its models' plain settings.
  SetDescriptor set{};
  // `tiltgate raw`: requests by function number. Every family fills it in; without it (a
  // test's family) raw refuses the family's buses.
  RawDescriptor raw{};
  // `tiltgate info` without the file the family's driver needs; none: info needs it.
  IdentifyDescriptor identify{};
};

using FamilyCommandsList = std::span<const FamilyCommands* const>;

// The commands of the families this build serves, in the order of registered_families(),
// generated from the folders families/families.cmake names. app/main.cpp asks for them once
// and hands them down.
FamilyCommandsList registered_family_commands();

// The commands of `family`; null when the list has none for it.
const FamilyCommands* find_commands(FamilyCommandsList commands, const FamilyDescriptor* family);

// `tiltgate sim COMMAND --protocol` choices: the family's protocols' short names, the default
// first; none when it has one protocol.
std::vector<std::string> simulator_protocol_choices(const FamilyDescriptor& family);
// "9bit or modbus (Modbus-ASCII)": the choices, each with its title where its short name does
// not already say it.
std::string simulator_protocols_help(const FamilyDescriptor& family);
// The ProtocolDescriptor name a choice stands for; empty when no protocol has that short name.
std::string_view protocol_of_choice(const FamilyDescriptor& family, std::string_view choice);

// What the family's simulator serves for its demo bus: the demo sensors as "model:address", in
// the demo bus's protocol.
SimulatorSetup demo_simulator_setup(const FamilyCommands& commands);

}  // namespace tiltgate
