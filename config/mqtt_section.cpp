// [mqtt]: the MQTT feed's broker, names and pacing (docs/northbound.md, "MQTT"). The table's presence turns
// the feed on (enabled = false keeps it written but off); host is then required.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <string>
#include <string_view>

#include "config/sections.h"
#include "config/state_dir_check.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;

namespace {

std::string hostname() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0 || name[0] == '\0') return "localhost";
  return name.data();
}

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

void read_file_key(TableReader& in, std::string_view key, std::string& out) {
  auto path = in.string(key);
  if (!path) return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(*path, ec))
    in.error(key, fmt::format("\"{}\" is not a file", *path));
  else
    out = *path;
}

// Where and how much of the backlog is kept (docs/northbound.md, "MQTT", "Backlog"). The
// store takes at least two segments of 512 KiB, hence 1 MiB at the least.
void read_backlog_keys(TableReader& in, MqttConfig& mqtt) {
  if (auto state_dir = in.string("state_dir")) {
    const std::filesystem::path dir = *state_dir;
    if (!dir.is_absolute()) {
      in.error("state_dir", fmt::format("\"{}\" is not an absolute path, expected a directory such "
                                        "as \"/var/lib/tiltgate\"",
                                        *state_dir));
    } else if (auto problem = state_dir_problem(dir / "mqtt")) {
      // Given on purpose, it must work: a backlog silently kept in memory would be lost on the
      // restart the setting was written for.
      in.error("state_dir", fmt::format("the backlog cannot be kept in {}: {}",
                                        (dir / "mqtt").string(), *problem));
    } else {
      mqtt.state_dir = *state_dir;
      mqtt.state_dir_given = true;
    }
  }
  if (auto buffer_mb = in.integer("buffer_mb", 1, 65536)) mqtt.buffer_mb = std::uint64_t(*buffer_mb);
  // Before the store, the most messages kept in memory; now, when written, still the most kept
  // (an upgraded configuration keeps its meaning).
  if (auto backlog = in.integer("backlog", 0, 100000000)) mqtt.backlog = std::size_t(*backlog);
}

}  // namespace

MqttConfig read_mqtt(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "mqtt", errors);
  MqttConfig mqtt;
  mqtt.enabled = in.boolean("enabled").value_or(true);
  if (auto host = in.string("host", mqtt.enabled ? Presence::required : Presence::optional)) {
    if (host->empty())
      in.error("host", "empty, expected the broker's host name or IP address");
    else
      mqtt.host = *host;
  }
  if (auto port = in.integer("port", 1, 65535)) mqtt.port = std::uint16_t(*port);
  const std::string host_name = hostname();
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
  // libmosquitto refuses a keep-alive under 5 s (mosquitto_connect: MOSQ_ERR_INVAL).
  if (auto keepalive = in.integer("keepalive_s", 5, 65535)) mqtt.keepalive_s = int(*keepalive);
  if (auto username = in.string("username")) mqtt.username = *username;
  if (auto password = in.string("password")) {
    if (!in.has("username"))
      in.error("password", "a password needs a username");
    else
      mqtt.password = *password;
  }
  read_file_key(in, "ca_file", mqtt.ca_file);
  read_file_key(in, "cert_file", mqtt.cert_file);
  read_file_key(in, "key_file", mqtt.key_file);
  if (in.has("cert_file") != in.has("key_file"))
    in.error(in.has("cert_file") ? "cert_file" : "key_file",
             "a client certificate needs both cert_file and key_file");
  if ((in.has("cert_file") || in.has("key_file")) && !in.has("ca_file"))
    in.error(in.has("cert_file") ? "cert_file" : "key_file",
             "a client certificate is sent over TLS only: give ca_file too");
  read_backlog_keys(in, mqtt);
  in.reject_unknown_keys();
  return mqtt;
}

}  // namespace tiltgate::config
