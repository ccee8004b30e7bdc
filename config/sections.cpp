#include "config/sections.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
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

// The rates a Rieker sensor can be set to (PROTOCOL-NOTES, Rieker: baud codes 1..8).
constexpr std::array<std::int64_t, 8> kRiekerBauds{9600,   19200,  38400,  62500,
                                                   115200, 125000, 128000, 250000};
// The rates a Dyna can be set to (PROTOCOL-NOTES, Dyna EEPROM location 22 baud codes).
constexpr std::array<std::int64_t, 5> kSpectronBauds{4800, 9600, 19200, 28800, 38400};

std::span<const std::int64_t> baud_rates(BusProtocol protocol) {
  if (protocol == BusProtocol::rieker) return kRiekerBauds;
  return kSpectronBauds;
}

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

BusProtocol protocol_from_name(std::string_view name) {
  if (name == "spectron-9bit") return BusProtocol::spectron_9bit;
  if (name == "spectron-modbus") return BusProtocol::spectron_modbus;
  return BusProtocol::rieker;
}

void read_baud(TableReader& in, BusConfig& bus, bool protocol_known) {
  const auto baud = in.integer("baud", kAnyInteger, kAnyIntegerMax);
  if (!protocol_known) return;
  const bool rieker = bus.protocol == BusProtocol::rieker;
  const std::span<const std::int64_t> rates = baud_rates(bus.protocol);
  const std::string expected = fmt::format("expected one of {}", fmt::join(rates, ", "));
  if (!baud) {
    // Rieker sensors ship at 125000 (the BusConfig default); the Dyna's factory rate is
    // not documented, so a Spectron bus must say which rate its sensors were set to.
    if (!rieker && !in.has("baud"))
      in.error("baud", fmt::format("required key is missing on {} buses; {}",
                                   protocol_name(bus.protocol), expected));
    return;
  }
  if (std::find(rates.begin(), rates.end(), *baud) == rates.end()) {
    in.error("baud", fmt::format("{} is not a {} baud rate, {}", *baud, protocol_name(bus.protocol),
                                 expected));
    return;
  }
  bus.baud = std::uint32_t(*baud);
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

// Raw-count conversion and the EEPROM window: only the Dyna has them.
void read_dyna_scaling(TableReader& in, SensorConfig& sensor) {
  if (auto v = in.number("counts_per_degree")) {
    if (*v == 0.0)
      in.error("counts_per_degree", "must not be 0 (raw counts are divided by it)");
    else
      sensor.counts_per_degree = *v;
  }
  if (auto v = in.number("zero_counts")) sensor.zero_counts = *v;
  // The application note's own example writes a reserved location; allowed on request only.
  if (auto v = in.boolean("eeprom_reserved_writes")) sensor.eeprom_reserved_writes = *v;
  if (!in.located().valid("model") || sensor.model == "dyna") return;
  for (std::string_view key : {"counts_per_degree", "zero_counts", "eeprom_reserved_writes"})
    if (in.has(key))
      in.error(key, fmt::format("applies to model \"dyna\" only, not \"{}\"", sensor.model));
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

std::string_view protocol_name(BusProtocol protocol) {
  switch (protocol) {
    case BusProtocol::rieker:
      return "rieker";
    case BusProtocol::spectron_9bit:
      return "spectron-9bit";
    case BusProtocol::spectron_modbus:
      return "spectron-modbus";
  }
  return "?";
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

ParsedBus read_bus(const toml::table& table, std::string path, ErrorList& errors) {
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
  auto protocol = in.choice("protocol", {"rieker", "spectron-9bit", "spectron-modbus"});
  if (protocol) bus.protocol = protocol_from_name(*protocol);
  const bool protocol_known = in.located().usable("protocol");
  read_baud(in, bus, protocol_known);
  read_reply_timeouts(in, bus);
  if (auto n = in.integer("retries", 0, 10)) bus.retries = int(*n);
  if (auto us = in.integer("gap_us", 0, 1'000'000)) {
    // PROTOCOL-NOTES, Rieker: packets from the master at least 1 ms apart.
    if (protocol_known && bus.protocol == BusProtocol::rieker && *us < 1000)
      in.error("gap_us",
               fmt::format("{} is too short for rieker sensors, expected 1000..1000000", *us));
    else
      bus.gap = microseconds(*us);
  }
  if (auto rs485 = in.boolean("rs485")) bus.rs485_kernel = *rs485;
  if (auto echo = in.boolean("echo")) bus.echo = *echo;
  // PROTOCOL-NOTES, Rieker: the master's own address is 0..65500.
  if (auto address = in.integer("master_address", 0, 65'500)) {
    if (protocol_known && bus.protocol != BusProtocol::rieker)
      in.error("master_address",
               fmt::format("applies to rieker buses only, not {}", protocol_name(bus.protocol)));
    bus.master_address = std::uint16_t(*address);
  }
  read_reopen_backoff(in, bus);
  in.reject_unknown_keys();
  return ParsedBus{std::move(bus), in.located()};
}

ParsedSensor read_sensor(const toml::table& table, std::string path, ErrorList& errors) {
  TableReader in(table, std::move(path), errors);
  SensorConfig sensor;
  sensor.line = in.located().header().line;
  if (auto name = in.string("name", Presence::required)) {
    check_name(in, "name", *name);
    sensor.name = *name;
  }
  if (auto bus = in.string("bus", Presence::required)) sensor.bus = *bus;
  if (auto model = in.choice("model", {"h6", "h4360", "dyna"}, Presence::required))
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
  read_dyna_scaling(in, sensor);
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
