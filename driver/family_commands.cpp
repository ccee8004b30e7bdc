#include "driver/family_commands.h"

#include <fmt/format.h>

#include <cctype>

namespace tiltgate {

namespace {

// "Modbus-ASCII" -> "modbusascii": how a short name may abbreviate its title.
std::string folded(std::string_view text) {
  std::string out;
  for (char c : text)
    if (std::isalnum(static_cast<unsigned char>(c)))
      out += char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

LineRequest RawExchange::request() {
  LineRequest line_request;
  line_request.bytes = bytes_;
  line_request.address_bytes = address_bytes_;
  line_request.framer = &framer();
  return line_request;
}

Expected<Done, std::string> check_raw_setup(const RawSetup& setup, const RawLimits& limits) {
  if (setup.function < limits.first_function || setup.function > limits.last_function)
    return Unexpected{fmt::format("--function: {} is not a {} {}..{}", setup.function,
                                  limits.function_kind, limits.first_function,
                                  limits.last_function)};
  if (setup.data.size() > limits.max_data)
    return Unexpected{
        fmt::format("--data: {} bytes, at most {}", setup.data.size(), limits.max_data)};
  return Done{};
}

const FamilyCommands* find_commands(FamilyCommandsList commands, const FamilyDescriptor* family) {
  for (const FamilyCommands* c : commands)
    if (c->family == family) return c;
  return nullptr;
}

std::vector<std::string> simulator_protocol_choices(const FamilyDescriptor& family) {
  std::vector<std::string> choices;
  if (family.protocols.size() < 2) return choices;
  for (const ProtocolDescriptor& protocol : family.protocols)
    choices.emplace_back(protocol.short_name);
  return choices;
}

std::string simulator_protocols_help(const FamilyDescriptor& family) {
  std::string help;
  for (const ProtocolDescriptor& protocol : family.protocols) {
    if (!help.empty()) help += " or ";
    help += protocol.short_name;
    if (folded(protocol.short_name) != folded(protocol.title))
      help += " (" + std::string(protocol.title) + ")";
  }
  return help;
}

std::string_view protocol_of_choice(const FamilyDescriptor& family, std::string_view choice) {
  for (const ProtocolDescriptor& protocol : family.protocols)
    if (protocol.short_name == choice) return protocol.name;
  return {};
}

SimulatorSetup demo_simulator_setup(const FamilyCommands& commands) {
  SimulatorSetup setup;
  for (const auto& sensors : {commands.demo.sensors, commands.demo.spare})
    for (const DemoSensor& sensor : sensors) {
      if (!setup.sensors.empty()) setup.sensors += ",";
      setup.sensors += std::string(sensor.model) + ":" + std::to_string(sensor.address);
    }
  setup.protocol = commands.demo.protocol;
  return setup;
}

}  // namespace tiltgate
