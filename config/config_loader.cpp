#include "config/config_loader.h"

#include <fmt/format.h>

#include <algorithm>

#include "config/aggregate_checks.h"
#include "config/cross_checks.h"
#include "config/listeners.h"
#include "config/map_files.h"
#include "config/pass_through_checks.h"
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
    "[server], [http], [mqtt], [sparkplug], [audit], [[bus]], [[sensor]] and [[aggregate]]";

std::string table_header(std::string_view name) {
  return name == "server" || name == "http" || name == "mqtt" || name == "sparkplug" ||
                 name == "audit"
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
  const std::vector<std::string> known{"server", "http",   "mqtt",      "sparkplug",
                                       "audit",  "bus",    "sensor", "aggregate"};
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

Config assemble(std::string path, ServerConfig server, HttpConfig http,
                std::vector<ParsedBus> buses, std::vector<ParsedSensor> sensors,
                std::vector<ParsedAggregate> aggregates) {
  Config config;
  config.path = std::move(path);
  config.server = server;
  config.http = std::move(http);
  if (!config.http.allow_given) config.http.allow = config.server.allow;
  for (ParsedBus& bus : buses) config.buses.push_back(std::move(bus.config));
  for (ParsedSensor& sensor : sensors) {
    sensor.config.address = std::uint32_t(sensor.address);  // range checked against its bus
    config.sensors.push_back(std::move(sensor.config));
  }
  for (ParsedAggregate& aggregate : aggregates)
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
  ServerConfig server;
  HttpConfig http;
  MqttConfig mqtt;
  SparkplugConfig sparkplug;
  AuditConfig audit;
  std::optional<Place> sparkplug_at;
  std::vector<ParsedBus> buses;
  std::vector<ParsedSensor> sensors;
  std::vector<ParsedAggregate> aggregates;
  for (auto&& [key, node] : root) {
    if (key == "server") {
      if (const toml::table* table = node.as_table())
        server = read_server(*table, errors);
      else
        errors.add(place_of(key.source()), "server",
                   fmt::format("expected a table ([server]), got {}", type_name(node.type())));
    } else if (key == "http") {
      if (const toml::table* table = node.as_table())
        http = read_http(*table, errors);
      else
        errors.add(place_of(key.source()), "http",
                   fmt::format("expected a table ([http]), got {}", type_name(node.type())));
    } else if (key == "mqtt") {
      if (const toml::table* table = node.as_table())
        mqtt = read_mqtt(*table, errors);
      else
        errors.add(place_of(key.source()), "mqtt",
                   fmt::format("expected a table ([mqtt]), got {}", type_name(node.type())));
    } else if (key == "sparkplug") {
      sparkplug_at = place_of(key.source());
      if (const toml::table* table = node.as_table())
        sparkplug = read_sparkplug(*table, errors);
      else
        errors.add(*sparkplug_at, "sparkplug",
                   fmt::format("expected a table ([sparkplug]), got {}", type_name(node.type())));
    } else if (key == "audit") {
      if (const toml::table* table = node.as_table())
        audit = read_audit(*table, errors);
      else
        errors.add(place_of(key.source()), "audit",
                   fmt::format("expected a table ([audit]), got {}", type_name(node.type())));
    } else if (key == "bus") {
      read_table_array("bus", key, node, errors, [&](const toml::table& table, std::string path) {
        buses.push_back(read_bus(table, std::move(path), errors, families));
      });
    } else if (key == "sensor") {
      read_table_array("sensor", key, node, errors,
                       [&](const toml::table& table, std::string path) {
                         sensors.push_back(read_sensor(table, std::move(path), errors, families));
                       });
    } else if (key == "aggregate") {
      read_table_array("aggregate", key, node, errors,
                       [&](const toml::table& table, std::string path) {
                         aggregates.push_back(read_aggregate(table, std::move(path), errors));
                       });
    } else {
      report_unknown_top_level(key, node, errors);
    }
  }
  if (nothing_served(root))
    errors.add(Place{}, "sensor", "no [[sensor]] defined, expected at least one");
  check_buses(buses, errors);
  check_tcp_ports(buses, server, errors);
  check_sensors(sensors, buses, errors, families);
  check_pass_through(buses, sensors, errors);
  // [server] state_dir is the feeds' default; their own key wins.
  if (!root.at_path("mqtt.state_dir")) mqtt.state_dir = server.state_dir;
  if (!root.at_path("sparkplug.state_dir")) sparkplug.state_dir = server.state_dir;
  if (sparkplug.enabled) check_feeds(mqtt, sparkplug, sparkplug_at.value_or(Place{}), errors);
  const std::size_t errors_before_maps = errors.size();
  ConfigErrors map_file_errors = load_sensor_maps(sensors, source_name, errors, families);
  check_aggregates(aggregates, sensors, buses,
                   map_file_errors.empty() && errors.size() == errors_before_maps, errors,
                   families);
  if (!errors.empty() || !map_file_errors.empty()) {
    ConfigErrors all = errors.take();
    all.insert(all.end(), map_file_errors.begin(), map_file_errors.end());
    return Unexpected(std::move(all));
  }
  Config config = assemble(std::string(source_name), server, std::move(http), std::move(buses),
                           std::move(sensors), std::move(aggregates));
  config.mqtt = std::move(mqtt);
  config.sparkplug = std::move(sparkplug);
  config.audit = audit;
  return config;
}

Expected<Config, ConfigErrors> load_config_file(const std::string& path, FamilyList families) {
  auto text = toml_input::read_text_file(path);
  if (!text) return Unexpected(ConfigErrors{ConfigError{path, 0, 0, "", text.error()}});
  return load_config_string(*text, path, families);
}

}  // namespace tiltgate
