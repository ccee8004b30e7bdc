#include "control/control_protocol.h"

#include <charconv>
#include <cmath>
#include <fmt/format.h>

namespace tiltgate::control {

namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

// Compact hex, two digits a byte: the control socket's own, not the trace log's spaced form.
std::string hex(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (const std::uint8_t b : bytes) {
    out += kDigits[b >> 4];
    out += kDigits[b & 0x0F];
  }
  return out;
}

std::optional<std::vector<std::uint8_t>> unhex(std::string_view text) {
  if (text.size() % 2 != 0) return std::nullopt;
  std::vector<std::uint8_t> bytes(text.size() / 2);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const auto [end, ec] = std::from_chars(text.data() + 2 * i, text.data() + 2 * i + 2,
                                           bytes[i], 16);
    if (ec != std::errc{} || end != text.data() + 2 * i + 2) return std::nullopt;
  }
  return bytes;
}

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

std::string milliseconds_or_dash(const std::optional<std::chrono::milliseconds>& ms) {
  return ms ? std::to_string(ms->count()) : "-";
}

std::optional<std::optional<std::chrono::milliseconds>> parse_milliseconds_or_dash(
    std::string_view word) {
  if (word == "-") return std::optional<std::chrono::milliseconds>{};
  const auto ms = number<std::int64_t>(word);
  if (!ms || *ms < 0) return std::nullopt;
  return std::optional<std::chrono::milliseconds>{std::chrono::milliseconds(*ms)};
}

constexpr std::pair<LineError, std::string_view> kLineErrors[] = {
    {LineError::timeout, "timeout"},
    {LineError::io, "io"},
    {LineError::closed, "closed"},
    {LineError::cancelled, "cancelled"},
    {LineError::expired, "expired"},
    {LineError::overloaded, "overloaded"}};

std::string_view word_of(LineError error) {
  for (const auto& [e, word] : kLineErrors)
    if (e == error) return word;
  return "io";
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
          [](const Transact& m) {
            return fmt::format("transact {} {} {} {} {} {} {}", m.address_bytes,
                               m.timeout.count(), m.retries, m.settle.count(),
                               m.expects_reply ? 1 : 0, milliseconds_or_dash(m.late_guard),
                               hex(m.bytes));
          },
          [](const FramerAnswer& m) { return std::string(m.done ? "done" : "more"); },
          [](const Follow& m) { return fmt::format("follow {} {}", m.from, m.to); },
          [](const Hold& m) { return fmt::format("hold {}", m.address); },
          [](const Release& m) { return fmt::format("release {}", m.address); },
          [](const SettingChanged& m) {
            const std::string outcome =
                m.nak ? fmt::format(" nak {}", *m.nak) : (m.timeout ? " timeout" : "");
            return fmt::format("setting {} {} {}{}", m.address, m.setting, m.value, outcome);
          },
          [](const ActingFor& m) { return "as " + m.who; },
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
          [](const Reset&) { return std::string("reset"); },
          [](const Received& m) { return "bytes " + hex(m.bytes); },
          [](const Ended& m) {
            const std::string_view status =
                m.busy ? "busy" : (m.error ? word_of(*m.error) : std::string_view("ok"));
            return fmt::format("end {} {} {} {} {}", status,
                               milliseconds_or_dash(m.timing.reply_delay), m.timing.late_replies,
                               milliseconds_or_dash(m.timing.late_delay), m.generation);
          },
          [](const Followed& m) { return m.sensor.empty() ? "ok" : "ok " + m.sensor; },
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
  if (w[0] == "more" && w.size() == 1) return CommandMessage{FramerAnswer{false}};
  if (w[0] == "done" && w.size() == 1) return CommandMessage{FramerAnswer{true}};
  if (w[0] == "follow" && w.size() == 3) {
    const auto from = number<std::uint32_t>(w[1]);
    const auto to = number<std::uint32_t>(w[2]);
    if (!from || !to) return malformed(line);
    return CommandMessage{Follow{*from, *to}};
  }
  if ((w[0] == "hold" || w[0] == "release") && w.size() == 2) {
    const auto address = number<std::uint32_t>(w[1]);
    if (!address) return malformed(line);
    if (w[0] == "hold") return CommandMessage{Hold{*address}};
    return CommandMessage{Release{*address}};
  }
  if (w[0] == "setting" && w.size() >= 4 && w.size() <= 6) {
    const auto address = number<std::uint32_t>(w[1]);
    const auto setting = number<std::uint8_t>(w[2]);
    const auto value = number<double>(w[3]);
    if (!address || !setting || !value || !std::isfinite(*value)) return malformed(line);
    SettingChanged changed{*address, *setting, *value, std::nullopt, false};
    if (w.size() == 5 && w[4] == "timeout") {
      changed.timeout = true;
    } else if (w.size() == 6 && w[4] == "nak") {
      changed.nak = number<std::uint8_t>(w[5]);
      if (!changed.nak) return malformed(line);
    } else if (w.size() != 4) {
      return malformed(line);
    }
    return CommandMessage{changed};
  }
  if (w[0] == "as" && w.size() >= 2)
    return CommandMessage{ActingFor{std::string(after_words(line, 1))}};
  if (w[0] == "transact" && w.size() == 8) {
    const auto address_bytes = number<std::size_t>(w[1]);
    const auto timeout = number<std::int64_t>(w[2]);
    const auto retries = number<int>(w[3]);
    const auto settle = number<std::int64_t>(w[4]);
    const auto late_guard = parse_milliseconds_or_dash(w[6]);
    const auto bytes = unhex(w[7]);
    if (!address_bytes || !timeout || !retries || !settle || !late_guard || !bytes ||
        *timeout < 0 || *settle < 0 || *retries < -1 || (w[5] != "0" && w[5] != "1") ||
        bytes->empty() || *address_bytes > bytes->size())
      return malformed(line);
    return CommandMessage{Transact{*address_bytes, std::chrono::milliseconds(*timeout), *retries,
                                   std::chrono::milliseconds(*settle), w[5] == "1", *late_guard,
                                   *bytes}};
  }
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
  if (w[0] == "reset" && w.size() == 1) return GatewayMessage{Reset{}};
  if (w[0] == "bytes" && w.size() == 2) {
    auto bytes = unhex(w[1]);
    if (!bytes) return malformed(line);
    return GatewayMessage{Received{std::move(*bytes)}};
  }
  if (w[0] == "ok") return GatewayMessage{Followed{std::string(after_words(line, 1))}};
  if (w[0] == "end" && w.size() == 6) {
    Ended ended;
    if (w[1] == "busy") {
      ended.busy = true;
      ended.error = LineError::timeout;
    } else if (w[1] != "ok") {
      bool known = false;
      for (const auto& [e, word] : kLineErrors)
        if (w[1] == word) ended.error = e, known = true;
      if (!known) return malformed(line);
    }
    const auto delay = parse_milliseconds_or_dash(w[2]);
    const auto late = number<std::uint32_t>(w[3]);
    const auto late_delay = parse_milliseconds_or_dash(w[4]);
    const auto generation = number<std::uint64_t>(w[5]);
    if (!delay || !late || !late_delay || !generation) return malformed(line);
    ended.timing = LineTiming{*delay, *late, *late_delay, false, std::nullopt};
    ended.generation = *generation;
    return GatewayMessage{ended};
  }
  return malformed(line);
}

}  // namespace tiltgate::control
