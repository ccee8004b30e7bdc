// [sparkplug]: the Sparkplug B edge node's broker, ids, pacing, state directory and store
// (docs/northbound.md, "Sparkplug B"). The table's presence turns the edge node on; host and
// group_id are then required; a relative state_dir is taken from the file's directory. The ids
// are checked with the Sparkplug topic rules (config/sparkplug_id.h), so `tiltgate check` refuses
// what a host could not subscribe to.
#include <fmt/format.h>

#include <filesystem>
#include <string>

#include "config/broker_keys.h"
#include "config/sections.h"
#include "config/sparkplug_id.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::Presence;
using toml_input::TableReader;

namespace {

// A group, edge node or host id: its Sparkplug rules, reported at its key.
std::optional<std::string> read_id(TableReader& in, std::string_view key, Presence presence) {
  auto id = in.string(key, presence);
  if (!id) return std::nullopt;
  if (auto problem = sparkplug::check_id(key, *id)) {
    in.error(key, fmt::format("{}; expected a Sparkplug id: UTF-8 text without '+', '#' and "
                              "'/'",
                              *problem));
    return std::nullopt;
  }
  return id;
}

}  // namespace

SparkplugConfig read_sparkplug(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "sparkplug", errors);
  SparkplugConfig sparkplug;
  sparkplug.enabled = true;
  BrokerKeys broker;
  read_broker_keys(in, true, broker);
  sparkplug.host = broker.host;
  sparkplug.port = broker.port;
  sparkplug.keepalive_s = broker.keepalive_s;
  sparkplug.username = broker.username;
  sparkplug.password = broker.password;
  sparkplug.ca_file = broker.ca_file;
  sparkplug.cert_file = broker.cert_file;
  sparkplug.key_file = broker.key_file;
  if (auto group = read_id(in, "group_id", Presence::required)) sparkplug.group_id = *group;
  sparkplug.edge_node_id = host_name();
  if (auto node = read_id(in, "edge_node_id", Presence::optional)) {
    sparkplug.edge_node_id = *node;
  } else if (!in.has("edge_node_id")) {
    if (auto problem = sparkplug::check_id("edge_node_id", sparkplug.edge_node_id))
      in.error("edge_node_id",
               fmt::format("the host name \"{}\" cannot be the default edge_node_id ({}): give "
                           "edge_node_id",
                           sparkplug.edge_node_id, *problem));
  }
  // Not the [mqtt] feed's default: both may run at once, and a broker disconnects the older of
  // two clients with one id.
  sparkplug.client_id = "tiltgate-sparkplug-" + sparkplug.edge_node_id;
  if (auto client_id = in.string("client_id")) {
    if (client_id->empty())
      in.error("client_id", "empty, expected a name unique among the broker's clients");
    else
      sparkplug.client_id = *client_id;
  }
  read_state_dir(in, errors.file(), sparkplug.state_dir);
  if (auto on_change = in.number_in("on_change_deg", 0.0, 360.0))
    sparkplug.on_change_deg = *on_change;
  if (auto min = in.integer("min_interval_ms", 0, 3600000))
    sparkplug.min_interval = std::chrono::milliseconds(*min);
  if (auto max = in.integer("max_interval_ms", 100, 3600000))
    sparkplug.max_interval = std::chrono::milliseconds(*max);
  if (in.has("min_interval_ms") || in.has("max_interval_ms")) {
    if (sparkplug.min_interval > sparkplug.max_interval)
      in.error(in.has("min_interval_ms") ? "min_interval_ms" : "max_interval_ms",
               fmt::format("min_interval_ms ({}) is above max_interval_ms ({})",
                           sparkplug.min_interval.count(), sparkplug.max_interval.count()));
  }
  sparkplug.primary_host_id = read_id(in, "primary_host_id", Presence::optional);
  if (auto commands = in.boolean("commands")) sparkplug.commands = *commands;
  if (auto n = in.integer("max_commands_per_s", 0, 100'000))
    sparkplug.max_commands_per_s = int(*n);
  // A fraction is allowed: a test fills a store of 0.05 MiB in seconds. The least still holds
  // two segments of records (store/record_store.h); 64 GiB is more than a gateway's disk.
  if (auto buffer = in.number_in("buffer_mb", 0.01, 65536)) sparkplug.buffer_mb = *buffer;
  in.reject_unknown_keys();
  return sparkplug;
}

}  // namespace tiltgate::config
