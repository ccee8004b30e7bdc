#include "commission/commission_options.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <string_view>

#include "config/config_loader.h"

namespace tiltgate {

namespace {

// The option a configuration key stands for: "bus[0].stop_bits" -> "--stop-bits".
std::string option_for_key(std::string_view key) {
  const std::size_t dot = key.rfind('.');
  std::string name(dot == std::string_view::npos ? key : key.substr(dot + 1));
  std::replace(name.begin(), name.end(), '_', '-');
  return "--" + name;
}

// The configuration's own place, for problems in a --config file.
UsageErrors config_file_errors(const ConfigErrors& errors, std::string_view path) {
  UsageErrors out;
  for (const ConfigError& e : errors) out.push_back(e.to_string());
  out.push_back(fmt::format("--config: {}: {} error(s)", path, errors.size()));
  return out;
}

struct GivenOption {
  std::string_view name;
  bool given;
};

// Options that describe a bus on the command line, which a configuration gives instead.
std::vector<GivenOption> command_line_bus_options(const BusOptions& o) {
  return {{"--port", !o.port.empty()},
          {"--protocol", !o.protocol.empty()},
          {"--baud", o.baud.has_value()},
          {"--parity", !o.parity.empty()},
          {"--stop-bits", o.stop_bits.has_value()},
          {"--master-address", o.master_address.has_value()},
          {"--model", !o.model.empty()},
          {"--device", !o.device.empty()}};
}

// Which options may go together: one source of the bus, and what each source needs.
UsageErrors combination_errors(const BusOptions& o) {
  UsageErrors errors;
  if (!o.config.empty()) {
    for (const GivenOption& option : command_line_bus_options(o)) {
      if (option.given)
        errors.push_back(fmt::format(
            "{}: not with --config (the configuration gives the bus and its sensors)",
            option.name));
    }
    if (o.sensor.empty() && o.bus.empty())
      errors.push_back("--config: give --sensor NAME (one sensor) or --bus NAME (a whole bus)");
    if (!o.sensor.empty() && !o.bus.empty())
      errors.push_back("--sensor: not with --bus (a sensor names its own bus)");
    if (!o.sensor.empty() && !o.addresses.empty())
      errors.push_back("--address: not with --sensor (the configuration gives its address)");
    return errors;
  }
  if (!o.sensor.empty()) errors.push_back("--sensor: needs --config FILE");
  if (!o.bus.empty()) errors.push_back("--bus: needs --config FILE");
  if (o.port.empty()) {
    errors.push_back("--port: required (the bus's tty, or its device server as tcp://HOST:PORT or "
                     "rfc2217://HOST:PORT), or --config FILE with --sensor or --bus");
    return errors;
  }
  if (o.addresses.empty() && !o.sensors_optional)
    errors.push_back("--address: required with --port");
  // Each sensor gets a unit id in the configuration the options stand for.
  if (o.addresses.size() > 247) errors.push_back("--address: at most 247 sensors at once");
  return errors;
}

// The model the command line's sensors get: the one given, else the first of the protocol's
// family that speaks it (a line without a protocol gets the first family's first protocol, as
// the loader does).
std::string command_line_model(const BusOptions& o, FamilyList families) {
  if (!o.model.empty() || families.empty()) return o.model;
  const std::string_view protocol =
      o.protocol.empty() ? families.front()->protocols.front().name : o.protocol;
  if (const ProtocolEntry entry = find_protocol(families, protocol); entry.family) {
    if (const ModelDescriptor* model = first_model_speaking(*entry.family, protocol))
      return std::string(model->name);
  }
  return {};
}

// Whether the sensors go without a driver: the command can, and their family's driver needs a
// file (its required keys) that --device did not give.
bool without_drivers(const BusOptions& o, FamilyList families) {
  if (!o.driver_optional || !o.device.empty() || o.addresses.empty()) return false;
  const ModelEntry model = find_model(families, command_line_model(o, families));
  return model.family != nullptr && !required_sensor_keys(*model.family).empty();
}

Expected<CommissionTarget, UsageErrors> from_command_line(const BusOptions& o,
                                                          FamilyList families);

// The bus from the command line, and each --address as a sensor without a driver: the bus is
// checked by the loader as ever, the addresses against the protocol's range.
Expected<CommissionTarget, UsageErrors> addresses_without_drivers(const BusOptions& o,
                                                                  FamilyList families) {
  BusOptions bus_only = o;
  bus_only.addresses.clear();
  bus_only.sensors_optional = true;
  auto target = from_command_line(bus_only, families);
  if (!target) return target;
  const ProtocolEntry protocol = find_protocol(families, target->bus.protocol);
  const std::string model = command_line_model(o, families);
  UsageErrors errors;
  int unit_id = 1;
  for (const std::int64_t address : o.addresses) {
    const AddressRange range = protocol.protocol->addresses;
    if (address < range.min || address > range.max) {
      errors.push_back(fmt::format("--address: {} is out of range for a {} bus, expected {}..{}",
                                   address, target->bus.protocol, range.min, range.max));
      continue;
    }
    SensorConfig sensor;
    sensor.name = fmt::format("address-{}", address);
    sensor.bus = std::string(kCommandLineBus);
    sensor.model = model;
    sensor.address = std::uint32_t(address);
    sensor.unit_id = std::uint8_t(unit_id++);
    target->sensors.push_back(std::move(sensor));
  }
  if (!errors.empty()) return Unexpected{std::move(errors)};
  target->model_source = o.model.empty() ? ModelSource::detected : ModelSource::option;
  target->without_drivers = true;
  return target;
}

Expected<CommissionTarget, UsageErrors> from_command_line(const BusOptions& o,
                                                          FamilyList families) {
  const std::string text = command_line_config(o, families);
  auto loaded = load_config_string(text, "command line", families);
  if (!loaded) {
    const bool bad_protocol = std::any_of(
        loaded.error().begin(), loaded.error().end(),
        [](const ConfigError& e) { return option_for_key(e.key) == "--protocol"; });
    UsageErrors errors;
    for (const ConfigError& e : loaded.error()) {
      const std::string option = option_for_key(e.key);
      // A model is only defaulted from a known protocol: its errors follow from that one.
      if (bad_protocol && option == "--model") continue;
      std::string message = fmt::format("{}: {}", option, e.message);
      if (errors.end() == std::find(errors.begin(), errors.end(), message))
        errors.push_back(std::move(message));
    }
    return Unexpected{std::move(errors)};
  }
  CommissionTarget target;
  target.bus = loaded->buses.front();
  if (o.sensors_optional && o.addresses.empty()) target.bus.pass_through.clear();
  target.sensors = std::move(loaded->sensors);
  target.model_source = o.model.empty() ? ModelSource::detected : ModelSource::option;
  target.control_socket = std::string(kDefaultControlSocket);
  return target;
}

Expected<CommissionTarget, UsageErrors> from_config_file(const BusOptions& o,
                                                         FamilyList families) {
  auto loaded = load_config_file(o.config, families);
  if (!loaded) return Unexpected{config_file_errors(loaded.error(), o.config)};
  const Config& config = *loaded;
  CommissionTarget target;
  target.control_socket = config.server.control_socket;
  std::string bus_name = o.bus;
  if (!o.sensor.empty()) {
    const auto sensor = std::find_if(config.sensors.begin(), config.sensors.end(),
                                     [&](const SensorConfig& s) { return s.name == o.sensor; });
    if (sensor == config.sensors.end()) {
      std::vector<std::string> names;
      for (const SensorConfig& s : config.sensors) names.push_back(s.name);
      return Unexpected{UsageErrors{fmt::format("--sensor: {} has no sensor \"{}\" (it has: {})",
                                                o.config, o.sensor, fmt::join(names, ", "))}};
    }
    target.sensors.push_back(*sensor);
    bus_name = sensor->bus;
  }
  const auto bus = std::find_if(config.buses.begin(), config.buses.end(),
                                [&](const BusConfig& b) { return b.name == bus_name; });
  if (bus == config.buses.end()) {
    std::vector<std::string> names;
    for (const BusConfig& b : config.buses) names.push_back(b.name);
    return Unexpected{UsageErrors{fmt::format("--bus: {} has no bus \"{}\" (it has: {})",
                                              o.config, bus_name, fmt::join(names, ", "))}};
  }
  target.bus = *bus;
  target.configured = configured_units(config, bus_name);
  if (!o.sensor.empty()) return target;

  UsageErrors errors;
  for (const SensorConfig& s : config.sensors) {
    if (s.bus != bus_name) continue;
    if (o.addresses.empty() ||
        std::find(o.addresses.begin(), o.addresses.end(), s.address) != o.addresses.end())
      target.sensors.push_back(s);
  }
  for (const std::int64_t address : o.addresses) {
    const bool configured =
        std::any_of(target.sensors.begin(), target.sensors.end(),
                    [&](const SensorConfig& s) { return s.address == address; });
    if (!configured)
      errors.push_back(fmt::format("--address: bus \"{}\" in {} has no sensor at address {}",
                                   bus_name, o.config, address));
  }
  if (target.sensors.empty() && errors.empty() && !o.sensors_optional)
    errors.push_back(fmt::format("--bus: bus \"{}\" in {} has no sensors", bus_name, o.config));
  if (!errors.empty()) return Unexpected{std::move(errors)};
  return target;
}

}  // namespace

std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string command_line_config(const BusOptions& o, FamilyList families) {
  std::string text = fmt::format("[[bus]]\nname = {}\nport = {}\n", toml_string(kCommandLineBus),
                                 toml_string(o.port));
  if (!o.protocol.empty()) text += fmt::format("protocol = {}\n", toml_string(o.protocol));
  if (o.baud) text += fmt::format("baud = {}\n", *o.baud);
  if (!o.parity.empty()) text += fmt::format("parity = {}\n", toml_string(o.parity));
  if (o.stop_bits) text += fmt::format("stop_bits = {}\n", *o.stop_bits);
  if (o.master_address) text += fmt::format("master_address = {}\n", *o.master_address);
  if (o.sensors_optional && o.addresses.empty()) {
    // The loader accepts a bus without sensors only when it passes unit ids through (there is
    // then something to serve); a bus to be scanned has none yet, so one stands in, on
    // protocols that can forward (from_command_line drops it again).
    const std::string_view protocol =
        o.protocol.empty() ? families.front()->protocols.front().name : o.protocol;
    if (const ProtocolEntry entry = find_protocol(families, protocol);
        entry.protocol && entry.protocol->forward)
      text += "pass_through = [1]\n";
  }

  // The model decides the driver.
  const std::string model = command_line_model(o, families);
  int unit_id = 1;
  for (const std::int64_t address : o.addresses) {
    text += fmt::format("\n[[sensor]]\nname = {}\nbus = {}\naddress = {}\nunit_id = {}\n",
                        toml_string(fmt::format("address-{}", address)),
                        toml_string(kCommandLineBus), address, unit_id);
    ++unit_id;
    if (!model.empty()) text += fmt::format("model = {}\n", toml_string(model));
    if (!o.device.empty())
      text += fmt::format("device = {}\n",
                          toml_string(std::filesystem::absolute(o.device).string()));
  }
  return text;
}

Expected<CommissionTarget, UsageErrors> resolve_bus_options(const BusOptions& options,
                                                            FamilyList families) {
  if (UsageErrors errors = combination_errors(options); !errors.empty())
    return Unexpected{std::move(errors)};
  auto target = !options.config.empty()             ? from_config_file(options, families)
                : without_drivers(options, families) ? addresses_without_drivers(options, families)
                                                     : from_command_line(options, families);
  if (!target) return target;
  target->families = families;
  if (!options.control_socket.empty()) target->control_socket = options.control_socket;
  target->via_gateway = options.via_gateway;
  if (target->via_gateway && target->control_socket.empty())
    return Unexpected{UsageErrors{
        "--via-gateway: the configuration has no control socket ([server] control_socket is "
        "empty); give --control-socket PATH"}};
  return target;
}

}  // namespace tiltgate
