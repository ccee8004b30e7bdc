// [mqtt]: the MQTT feed's broker, names and pacing (docs/northbound.md, "MQTT"). The table's presence turns
// the feed on (enabled = false keeps it written but off); host is then required.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>

#include "config/broker_keys.h"
#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;

namespace {

// An MQTT topic's levels are separated by '/'; '+' and '#' are subscription wildcards a
// published topic must not hold (MQTT 3.1.1, 4.7.1), and an empty level would make the feed's
// topics differ from what a subscriber writes.
void check_topic_prefix(TableReader& in, const std::string& prefix) {
  const bool wildcard = prefix.find_first_of("+#") != std::string::npos;
  const bool empty_level = prefix.empty() || prefix.front() == '/' || prefix.back() == '/' ||
                           prefix.find("//") != std::string::npos;
  const bool control = std::any_of(prefix.begin(), prefix.end(),
                                   [](char c) { return static_cast<unsigned char>(c) < 0x20; });
  if (wildcard || empty_level || control)
    in.error("topic_prefix",
             fmt::format("\"{}\" is not a topic prefix, expected levels separated by '/' with no "
                         "empty level and no '+' or '#', e.g. \"plant/line1\"",
                         prefix));
}

// Where and how much of the backlog is kept (docs/northbound.md, "MQTT"), as [sparkplug] reads
// its own: a relative state_dir is taken from the file's directory; whether it can be written
// is found when the feed starts (the service user's rights, not those of who runs check).
void read_backlog_keys(TableReader& in, const std::string& file, MqttConfig& mqtt) {
  read_state_dir(in, file, mqtt.state_dir);
  // A fraction is allowed, as for [sparkplug]: a test fills a store of 0.05 MiB in seconds.
  if (auto buffer = in.number_in("buffer_mb", 0.01, 65536)) mqtt.buffer_mb = *buffer;
  // Before the store, the most messages kept in memory; written, still the most kept (an
  // upgraded configuration keeps its meaning).
  if (auto backlog = in.integer("backlog", 0, 100000000)) mqtt.backlog = std::size_t(*backlog);
}

}  // namespace

MqttConfig read_mqtt(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "mqtt", errors);
  MqttConfig mqtt;
  mqtt.enabled = in.boolean("enabled").value_or(true);
  BrokerKeys broker;
  read_broker_keys(in, mqtt.enabled, broker);
  mqtt.host = broker.host;
  mqtt.port = broker.port;
  mqtt.keepalive_s = broker.keepalive_s;
  mqtt.username = broker.username;
  mqtt.password = broker.password;
  mqtt.ca_file = broker.ca_file;
  mqtt.cert_file = broker.cert_file;
  mqtt.key_file = broker.key_file;
  const std::string host_name = config::host_name();
  mqtt.client_id = "tiltgate-" + host_name;
  mqtt.topic_prefix = "tiltgate/" + host_name;
  if (auto client_id = in.string("client_id")) {
    // MQTT 3.1.1, 3.1.3.1: a server must accept 1..23 characters; mosquitto takes longer ones.
    if (client_id->empty())
      in.error("client_id", "empty, expected a name unique among the broker's clients");
    else
      mqtt.client_id = *client_id;
  }
  if (auto prefix = in.string("topic_prefix")) {
    check_topic_prefix(in, *prefix);
    mqtt.topic_prefix = *prefix;
  }
  if (auto qos = in.integer("qos", 0, 2)) mqtt.qos = int(*qos);
  if (auto interval = in.integer("interval_ms", 100, 3600000))
    mqtt.interval = std::chrono::milliseconds(*interval);
  if (auto on_change = in.number_in("on_change_deg", 0.0, 360.0)) mqtt.on_change_deg = *on_change;
  read_backlog_keys(in, errors.file(), mqtt);
  in.reject_unknown_keys();
  return mqtt;
}

}  // namespace tiltgate::config
