// The bus and sensor options the commissioning commands share (`info`, `watch`; later `scan`,
// `set`, `raw`): a tty (or a serial device server's tcp:// or rfc2217:// URL) and protocol on
// the command line, or a bus and sensors taken from a configuration file. Command-line values
// go through the configuration loader itself, so a bad protocol, baud, framing, address or
// port URL is refused exactly as it would be in a [[bus]] or [[sensor]], reported under the
// option's name instead of the key's.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "commission/configured_units.h"
#include "config/config.h"
#include "driver/expected.h"
#include "driver/family.h"

namespace tiltgate {

// As the command line gives them; empty / none for an option not given.
struct BusOptions {
  // Either a bus on the command line...
  std::string port;
  std::string protocol;  // none: the loader's default, the first family's first protocol
  std::optional<std::int64_t> baud;
  std::string parity;
  std::optional<std::int64_t> stop_bits;
  std::optional<std::int64_t> master_address;
  std::string model;   // none: the protocol's family's first model
  std::string device;  // a file for the family's `device` key, where its sensors take one
  // ... or one from a configuration: a sensor and its bus, or a whole bus.
  std::string config;
  std::string sensor;
  std::string bus;
  // Sensors by bus address: with --port, the sensors to talk to; with --bus, a choice among
  // the bus's configured sensors.
  std::vector<std::int64_t> addresses;
  // Whether the command can do without sensors (scan finds them): no --address is needed
  // with --port, and a --bus may have none configured.
  bool sensors_optional = false;
  // Whether the command can talk to a sensor without its driver (raw builds its own request,
  // info asks the device what it is): with --port and without --device, a sensor whose
  // family's driver needs a file (the family's required keys) is its address alone, with no
  // driver, instead of a usage error.
  bool driver_optional = false;
  // Through a running gateway's control socket: required (--via-gateway), or used when a
  // gateway there serves the tty. The socket: --control-socket, else the configuration's
  // [server] control_socket, else the default.
  bool via_gateway = false;
  std::string control_socket;
};

// Where a commissioned sensor's model comes from.
enum class ModelSource : std::uint8_t {
  option,         // --model
  configuration,  // the [[sensor]]'s model in --config FILE
  detected,       // neither: found by polling the sensor as each model of its family
};

// The bus to open and the sensors on it to talk to, validated as a configuration is.
struct CommissionTarget {
  BusConfig bus;
  std::vector<SensorConfig> sensors;
  ModelSource model_source = ModelSource::configuration;  // of every sensor's model
  FamilyList families;  // the families the bus and its sensors were checked against
  std::string control_socket;  // where a running gateway may serve the bus; empty: none
  bool via_gateway = false;    // only through that gateway, never the tty directly
  // The sensors get no driver: their family's needs a file the command line left out
  // (BusOptions::driver_optional). Each is then its address alone.
  bool without_drivers = false;
  // What the configuration file holds besides the bus (from --config; empty without one): what
  // a scan proposes to add must not be there already.
  ConfiguredUnits configured;
};

// Each message names the option (or the configuration file's place) it is about.
using UsageErrors = std::vector<std::string>;

// Protocols, models and their keys are those of `families`.
Expected<CommissionTarget, UsageErrors> resolve_bus_options(const BusOptions& options,
                                                            FamilyList families);

// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(std::string_view text);

// The name of the bus `--port` and its options describe.
inline constexpr std::string_view kCommandLineBus = "command-line";

// The configuration text that stands for a command-line bus (exposed for tests).
std::string command_line_config(const BusOptions& options, FamilyList families);

}  // namespace tiltgate
