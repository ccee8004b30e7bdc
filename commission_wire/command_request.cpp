#include "commission_wire/command_request.h"

#include <array>
#include <fmt/format.h>
#include <optional>
#include <string_view>

#include "commission_wire/json_fields.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

// The commands a gateway runs for a command line, and the section of the request each needs
// besides "bus" (empty: none).
struct RequestCommand {
  std::string_view name;
  std::string_view section;
};
constexpr std::array<RequestCommand, 5> kRequestCommands{{
    {"scan", "scan"},
    {"info", ""},
    {"watch", "watch"},
    {"set", "set"},
    {"raw", "raw"},
}};

json bus_options_json(const BusOptions& b) {
  return json{{"port", b.port},
              {"protocol", b.protocol},
              {"baud", json_or_null(b.baud)},
              {"parity", b.parity},
              {"stop_bits", json_or_null(b.stop_bits)},
              {"master_address", json_or_null(b.master_address)},
              {"model", b.model},
              {"device", b.device},
              {"config", b.config},
              {"sensor", b.sensor},
              {"bus", b.bus},
              {"addresses", b.addresses},
              {"sensors_optional", b.sensors_optional},
              {"driver_optional", b.driver_optional},
              {"via_gateway", b.via_gateway},
              {"control_socket", b.control_socket}};
}

BusOptions read_bus_options(const JsonObjectReader& r) {
  BusOptions b;
  b.port = r.string("port");
  b.protocol = r.string("protocol");
  b.baud = r.optional_integer<std::int64_t>("baud");
  b.parity = r.string("parity");
  b.stop_bits = r.optional_integer<std::int64_t>("stop_bits");
  b.master_address = r.optional_integer<std::int64_t>("master_address");
  b.model = r.string("model");
  b.device = r.string("device");
  b.config = r.string("config");
  b.sensor = r.string("sensor");
  b.bus = r.string("bus");
  b.addresses = r.integer_list<std::int64_t>("addresses");
  b.sensors_optional = r.boolean("sensors_optional");
  b.driver_optional = r.boolean("driver_optional");
  b.via_gateway = r.boolean("via_gateway");
  b.control_socket = r.string("control_socket");
  return b;
}

json scan_options_json(const ScanOptions& s) {
  return json{{"auto_baud", s.auto_baud},
              {"from", json_or_null(s.from)},
              {"to", json_or_null(s.to)},
              {"config_out", s.config_out},
              {"force", s.force},
              {"broadcast", s.broadcast},
              {"probe_timeout_ms", json_or_null(s.probe_timeout_ms)}};
}

ScanOptions read_scan_options(const JsonObjectReader& r) {
  ScanOptions s;
  s.auto_baud = r.boolean("auto_baud");
  s.from = r.optional_integer<std::int64_t>("from");
  s.to = r.optional_integer<std::int64_t>("to");
  s.config_out = r.string("config_out");
  s.force = r.boolean("force");
  s.broadcast = r.boolean("broadcast");
  s.probe_timeout_ms = r.optional_integer<std::int64_t>("probe_timeout_ms");
  return s;
}

json raw_options_json(const RawOptions& o) {
  return json{{"function", o.function}, {"data", o.data}};
}

// `data` stays the engineer's text: the raw engine checks it against the family's request shape
// and says what is wrong with it there, as for a local run.
RawOptions read_raw_options(const JsonObjectReader& r) {
  return {r.integer<std::int64_t>("function"), r.string("data")};
}

json watch_options_json(const WatchOptions& w) {
  return json{{"count", w.count}, {"interval_ms", w.interval_ms}};
}

WatchOptions read_watch_options(const JsonObjectReader& r) {
  return {r.integer<int>("count"), r.integer<int>("interval_ms")};
}

json set_arguments_json(const SetArguments& s) {
  return json{{"words", s.words}, {"permanent", s.permanent}};
}

SetArguments read_set_arguments(const JsonObjectReader& r) {
  return {r.string_list("words"), r.boolean("permanent")};
}

// The section `key`, read by `read` when it is there (and required), else the defaults.
template <class T>
T read_section(const JsonObjectReader& r, std::string_view key, bool required,
               T (*read)(const JsonObjectReader&)) {
  if (!required && !r.has(key)) return T{};
  return read(r.object(key));
}

CommandRequest read_request(const JsonObjectReader& r) {
  CommandRequest request;
  request.command = r.string("command");
  std::optional<RequestCommand> command;
  for (const RequestCommand& known : kRequestCommands)
    if (known.name == request.command) command = known;
  if (!command)
    throw JsonFieldError(fmt::format("unknown command \"{}\": expected scan, info, watch, set or raw",
                                     request.command));
  request.bus = read_bus_options(r.object("bus"));
  request.scan = read_section(r, "scan", command->section == "scan", read_scan_options);
  request.raw = read_section(r, "raw", command->section == "raw", read_raw_options);
  request.watch = read_section(r, "watch", command->section == "watch", read_watch_options);
  request.set = read_section(r, "set", command->section == "set", read_set_arguments);
  return request;
}

}  // namespace

json request_json(const CommandRequest& request) {
  return json{{"command", request.command},
              {"bus", bus_options_json(request.bus)},
              {"scan", scan_options_json(request.scan)},
              {"raw", raw_options_json(request.raw)},
              {"watch", watch_options_json(request.watch)},
              {"set", set_arguments_json(request.set)}};
}

Expected<CommandRequest, std::string> request_from_json(const json& j) {
  try {
    return read_request(JsonObjectReader(j, ""));
  } catch (const std::exception& e) {
    return Unexpected{fmt::format("not a command request: {}", e.what())};
  }
}

}  // namespace tiltgate
