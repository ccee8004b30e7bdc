// Reading the kinds of table: [server], [http] and [[sensor]] (sections.cpp), [mqtt]
// (mqtt_section.cpp), [sparkplug] (sparkplug_section.cpp), [audit] (audit_section.cpp),
// [redundancy] (redundancy_section.cpp), [[bus]] (bus_section.cpp). Each is checked on its own
// (types, ranges, keys that depend on another key of the same table); checks across tables are
// in config/cross_checks.h.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "config/config.h"
#include "toml/error_list.h"
#include "config/maps/map_reader.h"
#include "driver/family.h"

namespace tiltgate::toml_input {
class TableReader;
}  // namespace tiltgate::toml_input

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::Located;
using toml_input::TableReader;


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

struct ParsedAggregate {
  AggregateConfig config;
  Located where;
};

// [redundancy], with where its keys were written: its takeover_ms is checked against the
// buses' polls once they are read (config/redundancy_checks.h).
struct ParsedRedundancy {
  RedundancyConfig config;
  Located where;
};

// A state_dir key ([server], [mqtt], [sparkplug]): a directory, relative from the file's.
void read_state_dir(TableReader& in, const std::string& file, std::string& state_dir);
ServerConfig read_server(const toml::table& table, ErrorList& errors);
// [server] tls and plain_tcp (server_tls_section.cpp); after [server] port is read.
// The PEM file named at `key` (required), resolved against the config file's directory, and its
// contents: false, with the error added, when it is missing, empty or unreadable.
bool read_pem(TableReader& in, std::string_view key, const ErrorList& errors, std::string& path,
              std::string& contents);
void read_server_tls(TableReader& in, ServerConfig& server, ErrorList& errors);
HttpConfig read_http(const toml::table& table, ErrorList& errors);
// [http] users_file, tls_cert_file, tls_key_file and the session keys (the web console).
void read_console_keys(TableReader& in, HttpConfig& http, ErrorList& errors);
MqttConfig read_mqtt(const toml::table& table, ErrorList& errors);
// [sparkplug] (sparkplug_section.cpp); state_dir as written, resolved by the loader.
SparkplugConfig read_sparkplug(const toml::table& table, ErrorList& errors);
// [audit] (audit_section.cpp).
AuditConfig read_audit(const toml::table& table, ErrorList& errors);
// [record]: the long record's interval and how long it is kept.
RecordConfig read_record(const toml::table& table, ErrorList& errors);
// [redundancy] (redundancy_section.cpp).
ParsedRedundancy read_redundancy(const toml::table& table, ErrorList& errors);
// Protocols, bauds, addresses and models come from the families' descriptors.
ParsedBus read_bus(const toml::table& table, std::string path, ErrorList& errors,
                   FamilyList families);
ParsedSensor read_sensor(const toml::table& table, std::string path, ErrorList& errors,
                         FamilyList families);

// [[aggregate]] (aggregate_section.cpp); its names and points are checked against the sensors
// in aggregate_checks.cpp.
ParsedAggregate read_aggregate(const toml::table& table, std::string path, ErrorList& errors);

// "a or b or c": for messages that list what would do.
std::string or_list(std::span<const std::string_view> names);

}  // namespace tiltgate::config
