#include "control/control_protocol.h"

#include <charconv>
#include <fmt/format.h>

namespace tiltgate::control {

namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

// Words separated by single spaces.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  while (!line.empty()) {
    const std::size_t space = line.find(' ');
    out.push_back(line.substr(0, space));
    if (space == std::string_view::npos) break;
    line.remove_prefix(space + 1);
  }
  return out;
}

template <class T>
std::optional<T> number(std::string_view word) {
  T value{};
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc{} || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// The rest of the line after `count` words, for messages that end in free text.
std::string_view after_words(std::string_view line, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t space = line.find(' ');
    if (space == std::string_view::npos) return {};
    line.remove_prefix(space + 1);
  }
  return line;
}

Unexpected<std::string> malformed(std::string_view line) {
  return Unexpected{fmt::format("malformed message \"{}\"",
                                line.substr(0, std::min<std::size_t>(line.size(), 60)))};
}

}  // namespace

std::string format(const CommandMessage& message) {
  return std::visit(
      Overloaded{
          [](const Version& m) { return fmt::format("version {} {}", m.protocol, m.product); },
          [](const Hello& m) { return "hello " + m.port; },
          [](const Run& m) { return "run " + m.request; },
          [](const Stop&) { return std::string("stop"); },
      },
      message);
}

std::string format(const GatewayMessage& message) {
  return std::visit(
      Overloaded{
          [](const Version& m) { return fmt::format("version {} {}", m.protocol, m.product); },
          [](const BusGranted& m) {
            return fmt::format("bus {} {} {}", m.name, m.protocol, m.baud);
          },
          [](const Refused& m) { return "error " + m.reason; },
          [](const Event& m) { return "event " + m.json; },
          [](const Exit& m) { return fmt::format("exit {}", m.code); },
      },
      message);
}

namespace {

std::optional<Version> parse_version(const std::vector<std::string_view>& w) {
  if (w.size() != 3 || w[0] != "version") return std::nullopt;
  const auto protocol = number<unsigned>(w[1]);
  if (!protocol) return std::nullopt;
  return Version{*protocol, std::string(w[2])};
}

}  // namespace

std::string version_mismatch(std::string_view gateway, const std::optional<Version>& command) {
  const std::string commands =
      command ? fmt::format("this command (tiltgate {}) speaks control protocol {}",
                            command->product, command->protocol)
              : std::string("this command (an older tiltgate) speaks control protocol 1");
  return fmt::format("version {} {}: this gateway (tiltgate {}) speaks control protocol {}, {}: "
                     "run the tiltgate of the gateway's own version",
                     kProtocolVersion, gateway, gateway, kProtocolVersion, commands);
}

std::string older_gateway(std::string_view command_product) {
  return fmt::format("the running gateway speaks control protocol 1 (an older tiltgate), this "
                     "command (tiltgate {}) speaks control protocol {}: run the tiltgate of the "
                     "gateway's own version",
                     command_product, kProtocolVersion);
}

Expected<CommandMessage, std::string> parse_command(std::string_view line) {
  const std::vector<std::string_view> w = words(line);
  if (w.empty()) return malformed(line);
  if (const auto version = parse_version(w)) return CommandMessage{*version};
  if (w[0] == "hello" && w.size() >= 2) {
    const std::string_view port = after_words(line, 1);
    if (port.empty()) return malformed(line);
    return CommandMessage{Hello{std::string(port)}};
  }
  if (w[0] == "run" && w.size() >= 2) return CommandMessage{Run{std::string(after_words(line, 1))}};
  if (w[0] == "stop" && w.size() == 1) return CommandMessage{Stop{}};
  return malformed(line);
}

Expected<GatewayMessage, std::string> parse_gateway(std::string_view line) {
  const std::vector<std::string_view> w = words(line);
  if (w.empty()) return malformed(line);
  if (const auto version = parse_version(w)) return GatewayMessage{*version};
  if (w[0] == "bus" && w.size() == 4) {
    const auto baud = number<std::uint32_t>(w[3]);
    if (!baud) return malformed(line);
    return GatewayMessage{BusGranted{std::string(w[1]), std::string(w[2]), *baud}};
  }
  if (w[0] == "error") return GatewayMessage{Refused{std::string(after_words(line, 1))}};
  if (w[0] == "event" && w.size() >= 2)
    return GatewayMessage{Event{std::string(after_words(line, 1))}};
  if (w[0] == "exit" && w.size() == 2) {
    const auto code = number<int>(w[1]);
    if (!code || *code < 0 || *code > 255) return malformed(line);
    return GatewayMessage{Exit{*code}};
  }
  return malformed(line);
}

}  // namespace tiltgate::control
