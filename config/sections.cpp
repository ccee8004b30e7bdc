#include "config/sections.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <span>

#include "config/sensor_options.h"
#include "config/toml_reader.h"

namespace tiltgate::config {

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr auto kAnyInteger = std::numeric_limits<std::int64_t>::min();
constexpr auto kAnyIntegerMax = std::numeric_limits<std::int64_t>::max();

// Names appear in logs, metrics and on the command line: keep them to a safe alphabet.
void check_name(TableReader& in, std::string_view key, const std::string& name) {
  const bool safe = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-';
  });
  if (name.empty() || !safe)
    in.error(key, fmt::format("\"{}\" is not a valid name, expected one or more of the "
                              "letters A-Z a-z, digits 0-9, '_', '.' and '-'",
                              name));
}

bool is_ip_address(const std::string& text) {
  unsigned char buffer[sizeof(in6_addr)];
  return inet_pton(AF_INET, text.c_str(), buffer) == 1 ||
         inet_pton(AF_INET6, text.c_str(), buffer) == 1;
}

std::vector<std::string_view> protocol_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols) names.push_back(protocol.name);
  return names;
}

std::vector<std::string_view> model_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models) names.push_back(model.name);
  return names;
}

// The protocols whose master has an address of its own, and the first one's range (for a bus
// whose protocol is in error).
std::vector<std::string_view> protocols_with_master_address(FamilyList families,
                                                            AddressRange* first_range) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families) {
    for (const ProtocolDescriptor& protocol : family->protocols) {
      if (!protocol.master_addresses) continue;
      if (names.empty()) *first_range = *protocol.master_addresses;
      names.push_back(protocol.name);
    }
  }
  return names;
}

void read_baud(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol) {
  const auto baud = in.integer("baud", kAnyInteger, kAnyIntegerMax);
  if (protocol == nullptr) return;
  const std::span<const std::int64_t> rates = protocol->bauds;
  const std::string expected = fmt::format("expected one of {}", fmt::join(rates, ", "));
  if (!baud) {
    // A protocol whose sensors ship at a documented rate has it as the default; otherwise a
    // bus must say which rate its sensors were set to.
    if (protocol->default_baud)
      bus.baud = *protocol->default_baud;
    else if (!in.has("baud"))
      in.error("baud", fmt::format("required key is missing on {} buses; {}", bus.protocol,
                                   expected));
    return;
  }
  if (std::find(rates.begin(), rates.end(), *baud) == rates.end()) {
    in.error("baud", fmt::format("{} is not a {} baud rate, {}", *baud, bus.protocol, expected));
    return;
  }
  bus.baud = std::uint32_t(*baud);
}

std::vector<std::string_view> protocols_choosing_framing(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols)
      if (protocol.bus_chooses_framing) names.push_back(protocol.name);
  return names;
}

// parity and stop_bits: only where the protocol lets a bus choose its framing. Without parity
// the default is two stop bits, so a character keeps its length (Modbus over Serial Line
// V1.02, 2.5.1); parity with two stop bits is not a framing the transport offers.
void read_framing(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol,
                  FamilyList families) {
  const auto parity = in.choice("parity", {"even", "odd", "none"});
  const auto stop_bits = in.integer("stop_bits", 1, 2);
  if (protocol == nullptr) return;
  if (!protocol->bus_chooses_framing) {
    const std::vector<std::string_view> choosing = protocols_choosing_framing(families);
    for (std::string_view key : {"parity", "stop_bits"}) {
      if (!in.has(key)) continue;
      in.error(key, choosing.empty()
                        ? fmt::format("is not accepted on {} buses (their framing is fixed)",
                                      bus.protocol)
                        : fmt::format("applies to {} buses only, not {}", or_list(choosing),
                                      bus.protocol));
    }
    return;
  }
  const Framing fallback = protocol->framing;
  const bool odd = parity ? *parity == "odd" : fallback == Framing::eight_odd_one;
  const bool none = parity ? *parity == "none"
                           : fallback == Framing::eight_none_one || fallback == Framing::eight_none_two;
  const int stops = stop_bits ? int(*stop_bits) : (none ? 2 : 1);
  if (!none && stops == 2) {
    in.error("stop_bits", "2 with parity is not supported, expected 1 (or parity = \"none\")");
    return;
  }
  bus.framing = none ? (stops == 2 ? Framing::eight_none_two : Framing::eight_none_one)
                     : (odd ? Framing::eight_odd_one : Framing::eight_even_one);
}

// gap_us: the protocol's sensors may need a minimum quiet time between master packets; some
// protocols derive the default from the baud and framing.
void read_gap(TableReader& in, BusConfig& bus, ProtocolEntry protocol) {
  constexpr std::int64_t kMaxGap = 1'000'000;
  auto us = in.integer("gap_us", 0, kMaxGap);
  if (!us) {
    if (!in.has("gap_us") && protocol.protocol != nullptr && protocol.protocol->default_gap)
      bus.gap = protocol.protocol->default_gap(bus.baud,
                                               bus.framing.value_or(protocol.protocol->framing));
    return;
  }
  if (protocol.protocol != nullptr && *us < protocol.protocol->min_gap.count()) {
    in.error("gap_us", fmt::format("{} is too short for {} sensors, expected {}..{}", *us,
                                   protocol.family->name, protocol.protocol->min_gap.count(),
                                   kMaxGap));
    return;
  }
  bus.gap = microseconds(*us);
}

// master_address: only where the protocol gives the master an address of its own.
void read_master_address(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol,
                         FamilyList families) {
  AddressRange range;
  const std::vector<std::string_view> with_master = protocols_with_master_address(families, &range);
  if (protocol != nullptr && protocol->master_addresses) range = *protocol->master_addresses;
  auto address = in.integer("master_address", range.min, range.max);
  if (!address) return;
  if (protocol != nullptr && !protocol->master_addresses)
    in.error("master_address", fmt::format("applies to {} buses only, not {}",
                                           or_list(with_master), bus.protocol));
  bus.master_address = std::uint16_t(*address);
}

// timeout_ms, the cap of the adaptive per-sensor time-out, and the quiet guard after a
// time-out. Defaults follow what is given: the cap is at least the time-out, and the guard
// covers replies up to the cap (README, "Late replies").
void read_reply_timeouts(TableReader& in, BusConfig& bus) {
  if (auto ms = in.integer("timeout_ms", 1, 10'000)) bus.timeout = milliseconds(*ms);
  auto max_timeout = in.integer("max_timeout_ms", 1, 10'000);
  bus.max_timeout = max_timeout ? milliseconds(*max_timeout) : std::max(bus.max_timeout, bus.timeout);
  const Located& where = in.located();
  if (max_timeout && where.usable("timeout_ms") && bus.max_timeout < bus.timeout) {
    in.error("max_timeout_ms", fmt::format("{} is less than timeout_ms {}, expected at least {}",
                                           bus.max_timeout.count(), bus.timeout.count(),
                                           bus.timeout.count()));
    bus.max_timeout = bus.timeout;
  }
  if (auto ms = in.integer("late_guard_ms", 1, 10'000)) {
    bus.late_guard = milliseconds(*ms);
  } else {
    bus.late_guard = std::max(bus.max_timeout - bus.timeout, kMinDefaultLateGuard);
  }
}

void read_reopen_backoff(TableReader& in, BusConfig& bus) {
  if (auto ms = in.integer("reopen_min_ms", 10, 600'000)) bus.reopen_min = milliseconds(*ms);
  if (auto ms = in.integer("reopen_max_ms", 10, 3'600'000)) bus.reopen_max = milliseconds(*ms);
  const Located& where = in.located();
  if (where.usable("reopen_min_ms") && where.usable("reopen_max_ms") &&
      bus.reopen_max < bus.reopen_min) {
    in.error(in.has("reopen_max_ms") ? "reopen_max_ms" : "reopen_min_ms",
             fmt::format("reopen_max_ms {} is less than reopen_min_ms {}", bus.reopen_max.count(),
                         bus.reopen_min.count()));
  }
}

// pass_through: unit ids forwarded to the device with that address, where the protocol can
// forward Modbus requests. Checks across buses and sensors are in pass_through_checks.cpp.
void read_pass_through(TableReader& in, BusConfig& bus, const ProtocolDescriptor* protocol) {
  // Modbus unit ids and slave addresses share 1..247 (0 broadcasts, 248..255 are reserved).
  const auto ids = in.integers("pass_through", 1, 247);
  if (!ids) return;
  if (protocol != nullptr && protocol->forward == nullptr) {
    in.error("pass_through",
             fmt::format("protocol {} cannot forward Modbus requests", bus.protocol));
    return;
  }
  for (std::size_t i = 0; i < ids->size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if ((*ids)[j] != (*ids)[i]) continue;
      in.error("pass_through", fmt::format("unit id {} is listed twice", (*ids)[i]));
      bus.pass_through.clear();
      return;
    }
    bus.pass_through.push_back(std::uint8_t((*ids)[i]));
  }
}

// A family's keys through the TableReader, so errors carry the file, line and key.
class TableKeyReader final : public SensorKeyReader {
 public:
  TableKeyReader(TableReader& in, ErrorList& errors) : in_(in), errors_(errors) {}
  std::optional<double> number(std::string_view key) override { return in_.number(key); }
  std::optional<bool> boolean(std::string_view key) override { return in_.boolean(key); }
  std::optional<std::string> file_path(std::string_view key) override {
    auto name = in_.string(key);
    if (!name) return std::nullopt;
    if (name->empty()) {
      in_.error(key, "empty, expected a file name");
      return std::nullopt;
    }
    std::filesystem::path path(*name);
    if (path.is_relative()) path = std::filesystem::path(errors_.file()).parent_path() / path;
    return path.string();
  }
  void error(std::string_view key, std::string message) override {
    in_.error(key, std::move(message));
  }
  void file_errors(std::vector<FileError> errors) override {
    for (FileError& e : errors)
      errors_.add_elsewhere(ConfigError{std::move(e.file), e.line, e.column, std::move(e.key),
                                        std::move(e.message)});
  }

 private:
  TableReader& in_;
  ErrorList& errors_;
};

std::string quoted_models(const FamilyDescriptor& family) {
  std::vector<std::string> names;
  for (const ModelDescriptor& model : family.models) names.push_back(fmt::format("\"{}\"", model.name));
  return fmt::format("{}", fmt::join(names, " or "));
}

// Every family reads its keys (so each is type-checked and accepted); the sensor keeps its own
// family's, and a key of another family is refused once the model is known.
void read_family_keys(TableReader& in, SensorConfig& sensor, FamilyList families,
                      ErrorList& errors) {
  const ModelEntry model =
      in.located().valid("model") ? find_model(families, sensor.model) : ModelEntry{};
  for (const FamilyDescriptor* family : families) {
    TableKeyReader reader(in, errors);
    FamilyOptions options;
    family->read_sensor_keys(reader, options);
    if (family == model.family) sensor.family_options = std::move(options);
  }
  if (model.family == nullptr) return;
  for (std::string_view key : model.family->required_sensor_keys)
    if (!in.has(key))
      in.error(key, fmt::format("required key is missing on {} sensors", model.family->name));
  for (const FamilyDescriptor* family : families) {
    if (family == model.family) continue;
    for (std::string_view key : family->sensor_keys)
      if (in.has(key))
        in.error(key, fmt::format("applies to model {} only, not \"{}\"", quoted_models(*family),
                                  sensor.model));
  }
}

// map = "FILE" (loaded once every sensor is read) or an inline map table.
void read_map_key(TableReader& in, ParsedSensor& parsed, ErrorList& errors) {
  const toml::node* node = in.node("map");
  if (node == nullptr) return;
  if (const auto* file = node->as_string()) {
    if (file->get().empty()) return in.error("map", "empty, expected a map file name");
    parsed.map_file = file->get();
    in.accept("map");
  } else if (const toml::table* table = node->as_table()) {
    parsed.inline_map = read_map(*table, in.located().key_path("map"), errors);
    in.accept("map");
  } else {
    in.error("map", fmt::format("expected a map file name (a string) or an inline map (a "
                                "table), got {}",
                                type_name(node->type())));
  }
}

}  // namespace

std::string or_list(std::span<const std::string_view> names) {
  return fmt::format("{}", fmt::join(names, " or "));
}

ServerConfig read_server(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "server", errors);
  ServerConfig server;
  if (auto listen = in.string("listen")) {
    if (is_ip_address(*listen))
      server.listen = *listen;
    else
      in.error("listen", fmt::format("\"{}\" is not an IPv4 or IPv6 address, expected e.g. "
                                     "\"0.0.0.0\", \"127.0.0.1\" or \"::\"",
                                     *listen));
  }
  if (auto port = in.integer("port", 1, 65535)) server.port = std::uint16_t(*port);
  if (auto n = in.integer("max_clients", 1, 1024)) server.max_clients = int(*n);
  if (auto order = in.choice("word_order", {"big", "little"}))
    server.word_order = *order == "big" ? WordOrder::big : WordOrder::little;
  if (auto writes = in.boolean("writes")) server.writes = *writes;
  if (auto ms = in.integer("idle_timeout_ms", 1000, 86'400'000))
    server.idle_timeout = milliseconds(*ms);
  if (auto ms = in.integer("request_timeout_ms", 100, 600'000))
    server.request_timeout = milliseconds(*ms);
  if (auto ms = in.integer("write_timeout_ms", 100, 600'000))
    server.write_timeout = milliseconds(*ms);
  in.reject_unknown_keys();
  return server;
}

ParsedBus read_bus(const toml::table& table, std::string path, ErrorList& errors,
                   FamilyList families) {
  TableReader in(table, std::move(path), errors);
  BusConfig bus;
  bus.line = in.located().header().line;
  if (auto name = in.string("name", Presence::required)) {
    check_name(in, "name", *name);
    bus.name = *name;
  }
  if (auto port = in.string("port", Presence::required)) {
    if (port->empty()) in.error("port", "empty, expected a tty path such as \"/dev/ttyUSB0\"");
    bus.port = *port;
  }
  const std::vector<std::string_view> protocols = protocol_names(families);
  bus.protocol = protocols.empty() ? "" : std::string(protocols.front());
  if (auto protocol = in.choice("protocol", protocols)) bus.protocol = *protocol;
  const ProtocolEntry protocol = in.located().usable("protocol")
                                     ? find_protocol(families, bus.protocol)
                                     : ProtocolEntry{};
  read_baud(in, bus, protocol.protocol);
  read_reply_timeouts(in, bus);
  if (auto n = in.integer("retries", 0, 10)) bus.retries = int(*n);
  read_framing(in, bus, protocol.protocol, families);
  read_gap(in, bus, protocol);
  if (auto rs485 = in.boolean("rs485")) bus.rs485_kernel = *rs485;
  if (auto echo = in.boolean("echo")) bus.echo = *echo;
  read_master_address(in, bus, protocol.protocol, families);
  read_reopen_backoff(in, bus);
  read_pass_through(in, bus, protocol.protocol);
  in.reject_unknown_keys();
  return ParsedBus{std::move(bus), in.located()};
}

ParsedSensor read_sensor(const toml::table& table, std::string path, ErrorList& errors,
                         FamilyList families) {
  TableReader in(table, std::move(path), errors);
  SensorConfig sensor;
  sensor.line = in.located().header().line;
  if (auto name = in.string("name", Presence::required)) {
    check_name(in, "name", *name);
    sensor.name = *name;
  }
  if (auto bus = in.string("bus", Presence::required)) sensor.bus = *bus;
  if (auto model = in.choice("model", model_names(families), Presence::required))
    sensor.model = *model;
  const auto address = in.integer("address", kAnyInteger, kAnyIntegerMax, Presence::required);
  if (auto id = in.integer("unit_id", 1, 247, Presence::required))
    sensor.unit_id = std::uint8_t(*id);
  if (auto ms = in.integer("poll_ms", 10, 3'600'000)) sensor.poll = milliseconds(*ms);
  if (auto ms = in.integer("stale_ms", 10, 86'400'000)) {
    if (in.located().usable("poll_ms") && milliseconds(*ms) < sensor.poll)
      in.error("stale_ms", fmt::format("{} is less than poll_ms {}: every reading would be "
                                       "stale before the next poll",
                                       *ms, sensor.poll.count()));
    else
      sensor.stale_after = milliseconds(*ms);
  }
  read_family_keys(in, sensor, families, errors);
  read_mounting(in, sensor, errors);
  read_alarms(in, sensor, errors);
  read_offline(in, sensor);
  ParsedSensor parsed{std::move(sensor), address.value_or(0), in.located(), {}, {}};
  read_map_key(in, parsed, errors);
  in.reject_unknown_keys();
  parsed.where = in.located();
  return parsed;
}

}  // namespace tiltgate::config
