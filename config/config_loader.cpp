#include "config/config_loader.h"

#include <fmt/format.h>

#include <algorithm>

#include "config/aggregate_checks.h"
#include "config/cross_checks.h"
#include "config/listeners.h"
#include "config/map_files.h"
#include "config/pass_through_checks.h"
#include "config/redundancy_checks.h"
#include "config/sections.h"
#include "toml/text_file.h"
#include "toml/toml_parse.h"
#include "toml/toml_reader.h"

namespace tiltgate {

namespace config {

using toml_input::closest_key;
using toml_input::ErrorList;
using toml_input::Place;
using toml_input::place_of;
using toml_input::TableReader;
using toml_input::type_name;

namespace {

// The top-level tables a file may hold, written as they appear in a file.
constexpr std::string_view kTopLevel =
    "[server], [http], [mqtt], [sparkplug], [audit], [redundancy], [record], [[bus]], "
    "[[sensor]] and [[aggregate]]";

std::string table_header(std::string_view name) {
  return name == "server" || name == "http" || name == "mqtt" || name == "sparkplug" ||
                 name == "audit" || name == "redundancy" || name == "record"
             ? fmt::format("[{}]", name)
             : fmt::format("[[{}]]", name);
}

// [[bus]], [[sensor]] and [[aggregate]]: an array whose every element is a table.
template <class ReadOne>
void read_table_array(std::string_view name, const toml::key& key, const toml::node& node,
                      ErrorList& errors, ReadOne read_one) {
  const toml::array* array = node.as_array();
  if (array == nullptr) {
    errors.add(place_of(key.source()), std::string(name),
               fmt::format("expected an array of tables ({}), got {}", table_header(name),
                           type_name(node.type())));
    return;
  }
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    std::string path = fmt::format("{}[{}]", name, i);
    if (const toml::table* table = element.as_table())
      read_one(*table, std::move(path));
    else
      errors.add(place_of(element.source()), std::move(path),
                 fmt::format("expected a table, got {}", type_name(element.type())));
  }
}

void report_unknown_top_level(const toml::key& key, const toml::node& node, ErrorList& errors) {
  const bool is_table = node.is_table() || node.is_array_of_tables();
  const std::vector<std::string> known{"server", "http", "mqtt",   "sparkplug", "audit",
                                       "redundancy", "record", "bus", "sensor", "aggregate"};
  const std::string guess = closest_key(key.str(), known);
  std::string message = is_table ? "unknown table" : "unknown key at the top level";
  if (!guess.empty())
    message += fmt::format("; did you mean {}?", table_header(guess));
  else
    message += fmt::format("; expected the tables {}", kTopLevel);
  errors.add(place_of(key.source()), std::string(key.str()), std::move(message));
}

// Whether a [[bus]] lists unit ids to pass through, as written (whether or not they are
// valid: a bad list has its own error, and is still meant to be served).
bool lists_pass_through(const toml::node& bus) {
  const toml::table* table = bus.as_table();
  const toml::node* ids = table ? table->get("pass_through") : nullptr;
  return ids != nullptr && !(ids->is_array() && ids->as_array()->empty());
}

// A gateway with nothing to serve is a commissioning mistake, not a configuration. Unit ids
// passed through to a bus are something to serve.
bool nothing_served(const toml::table& root) {
  if (const toml::array* buses = root["bus"].as_array()) {
    if (std::any_of(buses->begin(), buses->end(), lists_pass_through)) return false;
  }
  const toml::node* node = root.get("sensor");
  return node == nullptr || (node->is_array() && node->as_array()->empty());
}

// A top-level table ([server], [http], ...): read by `read`, or an error when it is not a table.
template <class Section, class Read>
void read_section(std::string_view name, const toml::key& key, const toml::node& node,
                  ErrorList& errors, Section& section, Read read) {
  if (const toml::table* table = node.as_table())
    section = read(*table, errors);
  else
    errors.add(place_of(key.source()), std::string(name),
               fmt::format("expected a table ({}), got {}", table_header(name),
                           type_name(node.type())));
}

// Every top-level table of a file as read, before the checks across them.
struct Sections {
  ServerConfig server;
  HttpConfig http;
  MqttConfig mqtt;
  SparkplugConfig sparkplug;
  AuditConfig audit;
  RecordConfig record;
  std::optional<ParsedRedundancy> redundancy;  // none without the table
  std::optional<Place> sparkplug_at;  // where [sparkplug] was written, for check_feeds
  std::vector<ParsedBus> buses;
  std::vector<ParsedSensor> sensors;
  std::vector<ParsedAggregate> aggregates;
};

Sections read_sections(const toml::table& root, ErrorList& errors, FamilyList families) {
  Sections read;
  for (auto&& [key, node] : root) {
    if (key == "server") {
      read_section("server", key, node, errors, read.server, read_server);
    } else if (key == "http") {
      read_section("http", key, node, errors, read.http, read_http);
    } else if (key == "mqtt") {
      read_section("mqtt", key, node, errors, read.mqtt, read_mqtt);
    } else if (key == "sparkplug") {
      read.sparkplug_at = place_of(key.source());
      read_section("sparkplug", key, node, errors, read.sparkplug, read_sparkplug);
    } else if (key == "audit") {
      read_section("audit", key, node, errors, read.audit, read_audit);
    } else if (key == "redundancy") {
      read_section("redundancy", key, node, errors, read.redundancy, read_redundancy);
    } else if (key == "record") {
      read_section("record", key, node, errors, read.record, read_record);
    } else if (key == "bus") {
      read_table_array("bus", key, node, errors, [&](const toml::table& table, std::string path) {
        read.buses.push_back(read_bus(table, std::move(path), errors, families));
      });
    } else if (key == "sensor") {
      read_table_array("sensor", key, node, errors,
                       [&](const toml::table& table, std::string path) {
                         read.sensors.push_back(
                             read_sensor(table, std::move(path), errors, families));
                       });
    } else if (key == "aggregate") {
      read_table_array("aggregate", key, node, errors,
                       [&](const toml::table& table, std::string path) {
                         read.aggregates.push_back(
                             read_aggregate(table, std::move(path), errors));
                       });
    } else {
      report_unknown_top_level(key, node, errors);
    }
  }
  return read;
}

// The checks across tables, and the sensors' map files loaded (their errors are reported at
// the map file's own lines, so they come back apart).
ConfigErrors check_sections(const toml::table& root, Sections& read,
                            std::string_view source_name, ErrorList& errors,
                            FamilyList families) {
  if (nothing_served(root))
    errors.add(Place{}, "sensor", "no [[sensor]] defined, expected at least one");
  check_buses(read.buses, errors);
  check_tcp_ports(read.buses, read.server, errors);
  check_sensors(read.sensors, read.buses, errors, families);
  check_pass_through(read.buses, read.sensors, errors);
  if (read.redundancy) check_takeover(*read.redundancy, read.buses, read.sensors, errors);
  // [server] state_dir is the feeds' default; their own key wins.
  if (!root.at_path("mqtt.state_dir")) read.mqtt.state_dir = read.server.state_dir;
  if (!root.at_path("sparkplug.state_dir")) read.sparkplug.state_dir = read.server.state_dir;
  if (read.sparkplug.enabled)
    check_feeds(read.mqtt, read.sparkplug, read.sparkplug_at.value_or(Place{}), errors);
  const std::size_t errors_before_maps = errors.size();
  ConfigErrors map_file_errors = load_sensor_maps(read.sensors, source_name, errors, families);
  check_aggregates(read.aggregates, read.sensors, read.buses,
                   map_file_errors.empty() && errors.size() == errors_before_maps, errors,
                   families);
  return map_file_errors;
}

Config assemble(std::string path, Sections read) {
  Config config;
  config.path = std::move(path);
  config.server = read.server;
  config.http = std::move(read.http);
  if (!config.http.allow_given) config.http.allow = config.server.allow;
  config.mqtt = std::move(read.mqtt);
  config.sparkplug = std::move(read.sparkplug);
  config.audit = read.audit;
  config.record = read.record;
  if (read.redundancy) config.redundancy = read.redundancy->config;
  for (ParsedBus& bus : read.buses) config.buses.push_back(std::move(bus.config));
  for (ParsedSensor& sensor : read.sensors) {
    sensor.config.address = std::uint32_t(sensor.address);  // range checked against its bus
    config.sensors.push_back(std::move(sensor.config));
  }
  for (ParsedAggregate& aggregate : read.aggregates)
    config.aggregates.push_back(std::move(aggregate.config));
  return config;
}

}  // namespace
}  // namespace config

Expected<Config, ConfigErrors> load_config_string(std::string_view text,
                                                  std::string_view source_name,
                                                  FamilyList families) {
  using namespace config;
  auto parsed = toml_input::parse_toml(text, source_name);
  if (!parsed) {
    const toml_input::ParseFailure& failure = parsed.error();
    return Unexpected(ConfigErrors{ConfigError{std::string(source_name), failure.where.line,
                                               failure.where.column, "", failure.description}});
  }
  const toml::table root = std::move(*parsed);
  ErrorList errors{std::string(source_name)};
  Sections read = read_sections(root, errors, families);
  ConfigErrors map_file_errors = check_sections(root, read, source_name, errors, families);
  if (!errors.empty() || !map_file_errors.empty()) {
    ConfigErrors all = errors.take();
    all.insert(all.end(), map_file_errors.begin(), map_file_errors.end());
    return Unexpected(std::move(all));
  }
  return assemble(std::string(source_name), std::move(read));
}

Expected<Config, ConfigErrors> load_config_file(const std::string& path, FamilyList families) {
  auto text = toml_input::read_text_file(path);
  if (!text) return Unexpected(ConfigErrors{ConfigError{path, 0, 0, "", text.error()}});
  return load_config_string(*text, path, families);
}

}  // namespace tiltgate
