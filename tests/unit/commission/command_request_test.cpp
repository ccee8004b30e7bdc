// What a command line asks a gateway to run (commission_wire/command_request.h): each command's
// request spelled out on the wire and read back through text to the same request, the sections a
// command may leave out, and every field refused when left out or of the wrong type.
#include <doctest/doctest.h>

#include <fmt/format.h>

#include "commission_wire/command_request.h"
#include "unit/commission/support/aggregate_fields.h"
#include "unit/commission/support/json_fields_probe.h"

namespace tiltgate {
namespace {

using nlohmann::json;

// A request with a value other than its default in every field of every section.
CommandRequest full_request(std::string command) {
  CommandRequest r;
  r.command = std::move(command);
  r.bus.port = "/dev/ttyUSB0";
  r.bus.protocol = "rieker";
  r.bus.baud = 38400;
  r.bus.parity = "even";
  r.bus.stop_bits = 2;
  r.bus.master_address = 250;
  r.bus.model = "h6";
  r.bus.device = "/etc/tiltgate/profile.toml";
  r.bus.config = "/etc/tiltgate/tiltgate.toml";
  r.bus.sensor = "north_wall";
  r.bus.bus = "line1";
  r.bus.addresses = {223, 224};
  r.bus.sensors_optional = true;
  r.bus.driver_optional = true;
  r.bus.via_gateway = true;
  r.bus.control_socket = "/run/tiltgate/control.sock";
  r.scan.auto_baud = true;
  r.scan.from = 1;
  r.scan.to = 254;
  r.scan.config_out = "found.toml";
  r.scan.force = true;
  r.scan.broadcast = true;
  r.scan.probe_timeout_ms = 40;
  r.raw.function = 3;
  r.raw.data = "00 00 00 0A";
  r.watch.count = 10;
  r.watch.interval_ms = 250;
  r.set.words = {"filter", "5"};
  r.set.permanent = true;
  return r;
}

json full_wire(const std::string& command) {
  json j = json::parse(R"({
    "bus": {"port": "/dev/ttyUSB0", "protocol": "rieker", "baud": 38400, "parity": "even",
            "stop_bits": 2, "master_address": 250, "model": "h6",
            "device": "/etc/tiltgate/profile.toml", "config": "/etc/tiltgate/tiltgate.toml",
            "sensor": "north_wall", "bus": "line1", "addresses": [223, 224],
            "sensors_optional": true, "driver_optional": true, "via_gateway": true,
            "control_socket": "/run/tiltgate/control.sock"},
    "scan": {"auto_baud": true, "from": 1, "to": 254, "config_out": "found.toml", "force": true,
             "broadcast": true, "probe_timeout_ms": 40},
    "raw": {"function": 3, "data": "00 00 00 0A"},
    "watch": {"count": 10, "interval_ms": 250},
    "set": {"words": ["filter", "5"], "permanent": true}})");
  j["command"] = command;
  return j;
}

constexpr const char* kCommands[] = {"scan", "info", "watch", "set", "raw"};

TEST_CASE("each command's request is written with every section, every field set") {
  for (const char* command : kCommands) {
    CAPTURE(command);
    CHECK(request_json(full_request(command)) == full_wire(command));
  }
}

TEST_CASE("every field of a request and of each of its sections has its place on the wire") {
  const json wire = full_wire("scan");
  CHECK(wire.size() == test::aggregate_field_count<CommandRequest>());
  CHECK(wire.at("bus").size() == test::aggregate_field_count<BusOptions>());
  CHECK(wire.at("scan").size() == test::aggregate_field_count<ScanOptions>());
  CHECK(wire.at("raw").size() == test::aggregate_field_count<RawOptions>());
  CHECK(wire.at("watch").size() == test::aggregate_field_count<WatchOptions>());
  CHECK(wire.at("set").size() == test::aggregate_field_count<SetArguments>());
}

TEST_CASE("each command's request read back from its text is the request written") {
  for (const char* command : kCommands) {
    CAPTURE(command);
    const auto back = request_from_json(json::parse(request_json(full_request(command)).dump()));
    REQUIRE_MESSAGE(back.has_value(), back.error());
    CHECK(back->command == command);
    CHECK(request_json(*back) == full_wire(command));
  }
}

TEST_CASE("a request's empty optionals are null and come back empty") {
  CommandRequest plain;
  plain.command = "scan";
  const json written = request_json(plain);
  for (const char* key : {"baud", "stop_bits", "master_address"})
    CHECK(written["bus"].at(key).is_null());
  for (const char* key : {"from", "to", "probe_timeout_ms"}) CHECK(written["scan"].at(key).is_null());
  const auto back = request_from_json(written);
  REQUIRE(back.has_value());
  CHECK_FALSE(back->bus.baud.has_value());
  CHECK_FALSE(back->bus.stop_bits.has_value());
  CHECK_FALSE(back->bus.master_address.has_value());
  CHECK_FALSE(back->scan.from.has_value());
  CHECK_FALSE(back->scan.to.has_value());
  CHECK_FALSE(back->scan.probe_timeout_ms.has_value());
}

TEST_CASE("a request needs only its command's own section besides the bus") {
  for (const char* command : kCommands) {
    CAPTURE(command);
    json minimal = full_wire(command);
    for (const char* section : {"scan", "raw", "watch", "set"})
      if (section != std::string(command)) minimal.erase(section);
    const auto read = request_from_json(minimal);
    REQUIRE_MESSAGE(read.has_value(), read.error());
    // The sections left out are the defaults, the command's own as sent.
    const CommandRequest defaults;
    const json back = request_json(*read);
    for (const char* section : {"scan", "raw", "watch", "set"}) {
      CAPTURE(section);
      const json expected = section == std::string(command) ? full_wire(command)[section]
                                                            : request_json(defaults)[section];
      CHECK(back[section] == expected);
    }
    CHECK(back["bus"] == full_wire(command)["bus"]);
  }
}

TEST_CASE("a request without its command's section, or without the bus, is an error naming it") {
  for (const char* section : {"scan", "raw", "watch", "set"}) {
    json missing = full_wire(section);
    missing.erase(section);
    const auto read = request_from_json(missing);
    REQUIRE_FALSE(read.has_value());
    CHECK(read.error() == fmt::format("not a command request: field \"{}\" is missing", section));
  }
  json no_bus = full_wire("info");
  no_bus.erase("bus");
  CHECK(request_from_json(no_bus).error() == "not a command request: field \"bus\" is missing");
}

TEST_CASE("a section that is there is checked fully, even one the command does not use") {
  json info = full_wire("info");
  info["watch"].erase("interval_ms");
  const auto read = request_from_json(info);
  REQUIRE_FALSE(read.has_value());
  CHECK(read.error() == "not a command request: field \"watch.interval_ms\" is missing");
}

TEST_CASE("any field left out of any command's request is an error naming the field") {
  for (const char* command : kCommands)
    for (const test::JsonLeaf& leaf : test::json_leaves(full_wire(command))) {
      if (!leaf.in_object) continue;
      CAPTURE(command);
      CAPTURE(leaf.path);
      // A whole section may be left out; its fields may not.
      const auto read = request_from_json(test::without(full_wire(command), leaf));
      REQUIRE_FALSE(read.has_value());
      CHECK(read.error().find('"' + leaf.path + '"') != std::string::npos);
    }
}

TEST_CASE("any field of the wrong type in any command's request is an error naming the field") {
  for (const char* command : kCommands)
    for (const test::JsonLeaf& leaf : test::json_leaves(full_wire(command))) {
      CAPTURE(command);
      CAPTURE(leaf.path);
      const auto read = request_from_json(test::with(full_wire(command), leaf, json::array()));
      REQUIRE_FALSE(read.has_value());
      CHECK(read.error().find('"' + leaf.path + '"') != std::string::npos);
    }
  json fraction = full_wire("watch");
  fraction["watch"]["count"] = 2.5;
  CHECK(request_from_json(fraction).error() ==
        "not a command request: field \"watch.count\": expected an integer from -2147483648 to "
        "2147483647, got a number with a fraction");
  json big = full_wire("watch");
  big["watch"]["interval_ms"] = 4294967296;
  CHECK_FALSE(request_from_json(big).has_value());
}

TEST_CASE("an unknown command is an error naming it") {
  const auto read = request_from_json(full_wire("format-disk"));
  REQUIRE_FALSE(read.has_value());
  CHECK(read.error() ==
        "not a command request: unknown command \"format-disk\": expected scan, info, watch, set "
        "or raw");
}

TEST_CASE("a JSON value that is not an object is not a request, and throws nothing") {
  for (const json& value : {json::array({"scan"}), json("scan"), json(nullptr), json(true)}) {
    CAPTURE(value.dump());
    Expected<CommandRequest, std::string> read = CommandRequest{};
    CHECK_NOTHROW(read = request_from_json(value));
    REQUIRE_FALSE(read.has_value());
    CHECK(read.error().rfind("not a command request: expected a JSON object, got ", 0) == 0);
  }
  json section_as_text = full_wire("scan");
  section_as_text["scan"] = "--baud auto";
  CHECK(request_from_json(section_as_text).error() ==
        "not a command request: field \"scan\": expected an object, got a string");
}

}  // namespace
}  // namespace tiltgate
