// Reading the three kinds of table: [server], [[bus]] and [[sensor]]. Each is checked on its
// own here (types, ranges, keys that depend on another key of the same table); checks across
// tables are in config/cross_checks.h.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "config/config.h"
#include "config/error_list.h"
#include "config/map_reader.h"

namespace tiltgate::config {

struct ParsedBus {
  BusConfig config;
  Located where;
};

struct ParsedSensor {
  SensorConfig config;
  // As written; its range depends on the bus protocol, checked once the bus is known.
  std::int64_t address = 0;
  Located where;
  std::string map_file;                 // map = "FILE", as written
  std::optional<ParsedMap> inline_map;  // map = { ... } or [sensor.map]
};

ServerConfig read_server(const toml::table& table, ErrorList& errors);
ParsedBus read_bus(const toml::table& table, std::string path, ErrorList& errors);
ParsedSensor read_sensor(const toml::table& table, std::string path, ErrorList& errors);

// As written in the file: "rieker", "spectron-9bit", "spectron-modbus".
std::string_view protocol_name(BusProtocol protocol);

}  // namespace tiltgate::config
