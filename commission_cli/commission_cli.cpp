#include "commission_cli/commission_cli.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace tiltgate {

namespace {

// An option whose absence matters (the configuration's default applies then).
template <class T>
CLI::Option* add_optional(CLI::App& command, const std::string& name, std::optional<T>& target,
                          const std::string& help) {
  return command.add_option_function<T>(
      name, [&target](const T& value) { target = value; }, help);
}

std::string protocol_names(FamilyList families) {
  std::vector<std::string> names;
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols) names.emplace_back(protocol.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

// The protocol of the family's demo bus.
const ProtocolDescriptor* demo_protocol(const FamilyCommands& family) {
  const FamilyDescriptor* const own[] = {family.family};
  return find_protocol(own, family.demo.protocol).protocol;
}

// "--port PORT --protocol P [--baud B] --address A" for the family's demo bus, with the keys
// its sensors must give.
std::string example_bus(const FamilyCommands& family, std::string_view port) {
  std::string example = fmt::format("--port {} --protocol {}", port, family.demo.protocol);
  // A protocol without a factory rate needs the one its sensors were set to.
  const ProtocolDescriptor* protocol = demo_protocol(family);
  if (protocol && !protocol->default_baud)
    example += fmt::format(" --baud {}", family.demo.baud);
  example += fmt::format(" --address {}", family.demo.sensors.front().address);
  for (std::string_view key : required_sensor_keys(*family.family))
    if (key == "device") example += " --device profile.toml";
  return example;
}

// Each family's demo bus on /dev/ttyUSB0.
std::vector<std::string> example_buses(FamilyCommandsList families) {
  std::vector<std::string> examples;
  for (const FamilyCommands* family : families)
    if (!family->demo.sensors.empty()) examples.push_back(example_bus(*family, "/dev/ttyUSB0"));
  return examples;
}

// The first demo bus a serial device server can carry (raw TCP), for the help texts: not a
// 9-bit one (docs/operations.md, "Serial device servers").
std::string device_server_example(FamilyCommandsList families) {
  constexpr std::string_view kServer = "tcp://192.168.1.20:4001";
  for (const FamilyCommands* family : families) {
    const ProtocolDescriptor* protocol = demo_protocol(*family);
    if (family->demo.sensors.empty() || !protocol || protocol->framing == Framing::nine_bit)
      continue;
    return example_bus(*family, kServer);
  }
  return fmt::format("--port {}", kServer);
}

}  // namespace

std::string info_help_footer(FamilyCommandsList families) {
  std::string text = "Examples:\n";
  for (const std::string& bus : example_buses(families))
    text += fmt::format("  tiltgate info {}\n", bus);
  // Where the family's driver needs a file, info also goes without it.
  for (const FamilyCommands* family : families)
    if (family->identify.ask && !family->demo.sensors.empty() &&
        !required_sensor_keys(*family->family).empty())
      text += fmt::format("  tiltgate info --port /dev/ttyUSB0 --protocol {} --address {}   # "
                          "without --{}: what the device says of itself\n",
                          family->demo.protocol, family->demo.sensors.front().address,
                          fmt::join(required_sensor_keys(*family->family), ", --"));
  text += fmt::format("  tiltgate info {}\n", device_server_example(families));
  text += "  tiltgate info --config /etc/tiltgate/tiltgate.toml --bus line1 --address 5,6\n";
  text +=
      "Exit status: 0 every sensor answered; 1 one did not, or the tty cannot be used;\n"
      "2 usage error.";
  return text;
}

std::string watch_help_footer(FamilyCommandsList families) {
  std::string text = "Examples:\n";
  for (const std::string& bus : example_buses(families))
    text += fmt::format("  tiltgate watch {}\n", bus);
  text += fmt::format("  tiltgate watch {}\n", device_server_example(families));
  text += "  tiltgate watch --config /etc/tiltgate/tiltgate.toml --bus line1 --log angles.csv\n";
  text += "  tiltgate watch --config /etc/tiltgate/tiltgate.toml --sensor boom --count 10 "
          "--interval 200\n";
  text +=
      "On a terminal the table is redrawn in place until Ctrl-C; otherwise, or with --count,\n"
      "one line per sensor per round. Columns: address, serial, angles and tilt in degrees,\n"
      "ok/no-reply, age of the last reading (ms), readings per second.\n"
      "Exit status: 0 (Ctrl-C and SIGTERM too); 1 the tty cannot be used; 2 usage error.";
  return text;
}

std::string scan_help_footer(FamilyCommandsList families) {
  std::string text = "Examples:\n";
  for (const FamilyCommands* family : families) {
    if (family->demo.sensors.empty()) continue;
    std::string example = fmt::format("  tiltgate scan --port /dev/ttyUSB0 --protocol {}",
                                      family->demo.protocol);
    const ProtocolDescriptor* protocol = demo_protocol(*family);
    example += protocol && !protocol->default_baud
                   ? std::string(" --baud auto")
                   : fmt::format(" --config-out {}.toml", family->demo.protocol);
    for (std::string_view key : required_sensor_keys(*family->family))
      if (key == "device") example += " --device profile.toml";
    text += example + "\n";
  }
  text += "  tiltgate scan --port /dev/ttyUSB0 --from 1 --to 65000 --baud auto\n";
  text += "  tiltgate scan --port /dev/ttyUSB0 --broadcast      # one sensor on the bus only\n";
  text += "  tiltgate scan --port rfc2217://192.168.1.20:4001 --baud auto   # a device server\n";
  text += "  tiltgate scan --config /etc/tiltgate/tiltgate.toml --bus line1\n";
  text +=
      "Without --from/--to the protocol's usual addresses and its factory addresses are\n"
      "probed. One row per address that answered: address, baud, model, serial, firmware,\n"
      "lock level, and \"probable collision\" where garbled replies suggest two sensors at one\n"
      "address. --config-out writes a configuration of the sensors found for `tiltgate check`.\n"
      "Exit status: 0 a sensor answered; 1 none did, or the tty cannot be used; 2 usage error.";
  return text;
}

std::string set_help_footer(FamilyCommandsList families) {
  std::string text = "Settings (the sensor's model decides which it has; an unknown one lists them):\n";
  text +=
      "  address N            move the sensor to bus address N (refused when one answers there)\n"
      "  baud RATE            set the sensor's rate, restart it and follow it there\n"
      "  filter N             filter response / damping\n"
      "  zero-x DEG, zero-y DEG  zero offsets\n"
      "  zero-here [--permanent]  zero to the current angle (temporary unless --permanent)\n"
      "  restart              restart the sensor and wait for it\n"
      "  NAME VALUE...        the model's own settings by name (an unknown SETTING lists them)\n";
  for (const FamilyCommands* family : families)
    for (const CompoundSetting& compound : family->set.compound_settings)
      text += fmt::format("  {:<20} {} sensors: writes {}\n",
                          fmt::format("{} {}", compound.name, compound.values), family->title,
                          fmt::join(compound.parts, " then "));
  text += "Examples:\n";
  const std::vector<std::string> buses = example_buses(families);
  if (!buses.empty()) {
    text += fmt::format("  tiltgate set {} address 7\n", buses.front());
    text += fmt::format("  tiltgate set {} zero-here --permanent\n", buses.front());
    text += fmt::format("  tiltgate set {} address 7\n", device_server_example(families));
  }
  // A family without a restart command has only its sensors' own settings, named by them.
  std::size_t bus = 1;
  for (const FamilyCommands* family : families) {
    if (family->demo.sensors.empty() || family == families.front()) continue;
    const bool restarts = family->set.command_value &&
                          family->set.command_value(SensorCommand::restart).has_value();
    if (bus < buses.size())
      text += fmt::format("  tiltgate set {} {}\n", buses[bus++], restarts ? "restart" : "NAME VALUE");
  }
  text += "  tiltgate set --config /etc/tiltgate/tiltgate.toml --sensor boom address 7\n";
  text += "  tiltgate set --config /etc/tiltgate/tiltgate.toml --sensor boom zero-x -1.5\n";
  text +=
      "With --config FILE --sensor NAME a new address or baud is also written into FILE, in\n"
      "place. Exit status: 0 done and read back; 1 the sensor refused (the reason is printed),\n"
      "did not answer, the new address is taken, or the tty cannot be used; 2 usage error or a\n"
      "value out of range (nothing sent).";
  return text;
}

std::string raw_help_footer(FamilyCommandsList families) {
  std::string text = "--function and --data on each protocol:\n";
  for (const FamilyCommands* family : families)
    if (!family->raw.function_help.empty())
      text += fmt::format("  {}\n", family->raw.function_help);
  text += "Examples:\n";
  const std::vector<std::string> buses = example_buses(families);
  if (!buses.empty()) {
    text += fmt::format("  tiltgate raw {} --function 37\n", buses.front());
    text += fmt::format("  tiltgate raw {} --function 37\n", device_server_example(families));
  }
  text += "  tiltgate raw --config /etc/tiltgate/tiltgate.toml --sensor boom --function 5 --data 04\n";
  text +=
      "The request is sent once. Output: the bytes sent and received in hex, the checksum's\n"
      "verdict, and the reply decoded. Exit status: 0 a reply; 1 a NAK, an exception, no reply,\n"
      "or the tty cannot be used; 2 usage error.";
  return text;
}

void add_bus_options(CLI::App& command, BusOptions& options, FamilyList families,
                     bool* auto_baud) {
  command
      .add_option("--port", options.port,
                  "the bus's tty, e.g. /dev/ttyUSB0, or a serial device server: "
                  "tcp://HOST:PORT (raw; the rate is the server's setting) or "
                  "rfc2217://HOST:PORT (the rate and framing set from here)")
      ->group("Bus on the command line");
  command
      .add_option("--protocol", options.protocol,
                  fmt::format("{} (default: {})", protocol_names(families),
                              families.front()->protocols.front().name))
      ->group("Bus on the command line");
  if (auto_baud) {
    command
        .add_option_function<std::string>(
            "--baud",
            [&options, auto_baud](const std::string& value) {
              if (value == "auto") {
                *auto_baud = true;
                return;
              }
              std::int64_t baud = 0;
              if (!CLI::detail::lexical_cast(value, baud))
                throw CLI::ValidationError("--baud", "a rate in baud, or auto: " + value);
              options.baud = baud;
            },
            "the rate the sensors are set to (default: the protocol's factory rate), or auto: "
            "every rate the protocol allows")
        ->group("Bus on the command line");
  } else {
    add_optional(command, "--baud", options.baud,
                 "the rate the sensors are set to (default: the protocol's factory rate)")
        ->group("Bus on the command line");
  }
  command.add_option("--parity", options.parity, "even, odd or none, where the protocol lets "
                                                 "the bus choose (default: the protocol's)")
      ->group("Bus on the command line");
  add_optional(command, "--stop-bits", options.stop_bits, "1 or 2, where the protocol lets the "
                                                          "bus choose")
      ->group("Bus on the command line");
  add_optional(command, "--master-address", options.master_address,
               "the master's own address, where the protocol has one")
      ->group("Bus on the command line");
  command.add_option("--model", options.model,
                     "the sensors' model, which decides the driver (default: the protocol's "
                     "first model)")
      ->group("Bus on the command line");
  command.add_option("--device", options.device,
                     "a device profile, for sensors whose family takes one (device = FILE)")
      ->group("Bus on the command line");
  command.add_option("-c,--config", options.config, "take the bus from this configuration file")
      ->group("Bus from a configuration");
  command.add_option("--sensor", options.sensor, "with --config: this sensor, on its bus")
      ->group("Bus from a configuration");
  command.add_option("--bus", options.bus, "with --config: this bus, all its sensors")
      ->group("Bus from a configuration");
  command
      .add_flag("--via-gateway", options.via_gateway,
                "only through the running gateway that owns the tty (its control socket), "
                "which keeps serving every other sensor; without it, a running gateway is used "
                "when it owns the tty, else the tty is opened directly")
      ->group("Through a running gateway");
  command
      .add_option("--control-socket", options.control_socket,
                  fmt::format("the gateway's control socket (default: the configuration's "
                              "[server] control_socket, else {})",
                              kDefaultControlSocket))
      ->group("Through a running gateway");
  command
      .add_option("--address", options.addresses,
                  "the sensors' bus addresses, A[,B...] (with --bus: some of its sensors)")
      ->delimiter(',')
      ->group("Sensors");
}

}  // namespace tiltgate
