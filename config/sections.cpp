#include "config/sections.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <span>

#include "config/alarm_options.h"
#include "config/host_names.h"
#include "config/sensor_options.h"
#include "driver/text_list.h"
#include "driver/visible_text.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::type_name;
using toml_input::kAnyInteger;
using toml_input::kAnyIntegerMax;
using toml_input::check_name;
using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;

namespace {

using std::chrono::milliseconds;

// allow = ["10.0.0.0/8", "::1"]: the list, or none if absent or malformed (reported).
std::optional<AddressAllowList> read_allow_list(TableReader& in, std::string_view key) {
  const auto entries = in.strings(key);
  if (!entries) return std::nullopt;
  auto list = AddressAllowList::parse(*entries);
  if (!list) {
    in.error(key, list.error() + ", expected addresses or networks such as \"192.168.1.20\", "
                                 "\"10.0.0.0/8\" or \"::1\"");
    return std::nullopt;
  }
  return std::move(*list);
}

// [http] server_names: each a host name (letters, digits, '-' in dot-separated labels of at
// most 63) or an IP address, at most 32 of them; a port is not part of a name.
void read_server_names(TableReader& in, HttpConfig& http) {
  auto names = in.strings("server_names");
  if (!names) return;
  if (names->empty() || names->size() > 32)
    return in.error("server_names", fmt::format("{} names, expected 1 to 32", names->size()));
  for (const std::string& name : *names)
    if (!is_ip_address(name) && !is_host_name(name))
      return in.error("server_names",
                      fmt::format("\"{}\" is not a host name or an IP address, expected e.g. "
                                  "\"gw-3.plant.example\" or \"10.0.0.5\" (no port)",
                                  visible_text(name)));
  http.server_names = std::move(*names);
}

std::vector<std::string_view> model_names(FamilyList families) {
  std::vector<std::string_view> names;
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models) names.push_back(model.name);
  return names;
}

// A family's keys through the TableReader, so errors carry the file, line and key.
class TableKeyReader final : public SensorKeyReader {
 public:
  TableKeyReader(TableReader& in, ErrorList& errors, FamilyList families)
      : in_(in), errors_(errors), families_(families) {}
  std::optional<double> number(std::string_view key) override { return in_.number(key); }
  std::optional<bool> boolean(std::string_view key) override { return in_.boolean(key); }
  std::optional<std::string> file_path(std::string_view key) override {
    auto name = in_.string(key);
    if (!name) return std::nullopt;
    if (name->empty()) {
      in_.error(key, "empty, expected a file name");
      return std::nullopt;
    }
    std::filesystem::path path(*name);
    if (path.is_relative()) path = std::filesystem::path(errors_.file()).parent_path() / path;
    return path.string();
  }
  void error(std::string_view key, std::string message) override {
    in_.error(key, std::move(message));
  }
  std::vector<std::string_view> setting_names() const override {
    return model_setting_names(families_);
  }
  void file_errors(FileErrors errors) override {
    for (FileError& e : errors) errors_.add_elsewhere(std::move(e));
  }

 private:
  TableReader& in_;
  ErrorList& errors_;
  FamilyList families_;
};

std::string quoted_models(const FamilyDescriptor& family) {
  std::vector<std::string> names;
  for (const ModelDescriptor& model : family.models) names.push_back(fmt::format("\"{}\"", model.name));
  return fmt::format("{}", fmt::join(names, " or "));
}

// Every family reads its keys (so each is type-checked and accepted); the sensor keeps its own
// family's, and a key of another family is refused once the model is known.
void read_family_keys(TableReader& in, SensorConfig& sensor, FamilyList families,
                      ErrorList& errors) {
  const ModelEntry model =
      in.located().valid("model") ? find_model(families, sensor.model) : ModelEntry{};
  for (const FamilyDescriptor* family : families) {
    TableKeyReader reader(in, errors, families);
    FamilyOptions options;
    family->read_sensor_keys(reader, options);
    if (family == model.family) sensor.family_options = std::move(options);
  }
  if (model.family == nullptr) return;
  for (const SensorKey& key : model.family->sensor_keys)
    if (key.required && !in.has(key.name))
      in.error(key.name, fmt::format("required key is missing on {} sensors", model.family->name));
  for (const FamilyDescriptor* family : families) {
    if (family == model.family) continue;
    for (const SensorKey& key : family->sensor_keys)
      if (in.has(key.name))
        in.error(key.name, fmt::format("applies to model {} only, not \"{}\"",
                                       quoted_models(*family), sensor.model));
  }
}

// map = "FILE" (loaded once every sensor is read) or an inline map table.
void read_map_key(TableReader& in, ParsedSensor& parsed, ErrorList& errors, FamilyList families) {
  const toml::node* node = in.node("map");
  if (node == nullptr) return;
  if (const auto* file = node->as_string()) {
    if (file->get().empty()) return in.error("map", "empty, expected a map file name");
    parsed.map_file = file->get();
    in.accept("map");
  } else if (const toml::table* table = node->as_table()) {
    parsed.inline_map = read_map(*table, in.located().key_path("map"), errors, families);
    in.accept("map");
  } else {
    in.error("map", fmt::format("expected a map file name (a string) or an inline map (a "
                                "table), got {}",
                                type_name(node->type())));
  }
}

}  // namespace

std::string or_list(std::span<const std::string_view> names) {
  return fmt::format("{}", fmt::join(names, " or "));
}

void read_state_dir(TableReader& in, const std::string& file, std::string& state_dir) {
  if (auto dir = in.string("state_dir")) {
    if (dir->empty())
      in.error("state_dir", "empty, expected a directory the gateway may write, e.g. "
                            "\"/var/lib/tiltgate\"");
    else if (std::filesystem::path path(*dir); path.is_relative())
      state_dir = (std::filesystem::path(file).parent_path() / path).string();
    else
      state_dir = *dir;
  }
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
  read_server_tls(in, server, errors);
  if (auto n = in.integer("max_clients_per_host", 1, 1024)) server.max_clients_per_host = int(*n);
  if (auto n = in.integer("threads", 1, 64)) server.threads = int(*n);
  if (auto order = in.choice("word_order", {"big", "little"}))
    server.word_order = *order == "big" ? WordOrder::big : WordOrder::little;
  if (auto writes = in.boolean("writes")) server.writes = *writes;
  if (auto allow = read_allow_list(in, "allow")) {
    if (allow->entries().empty())
      in.error("allow", "empty: no client could connect (leave allow out to allow every address)");
    server.allow = *allow;
  }
  // Writes from the hosts that may connect, unless narrowed.
  server.write_allow = server.allow;
  if (auto write_allow = read_allow_list(in, "write_allow")) server.write_allow = *write_allow;
  if (auto ms = in.integer("idle_timeout_ms", 1000, 86'400'000))
    server.idle_timeout = milliseconds(*ms);
  if (auto ms = in.integer("request_timeout_ms", 100, 600'000))
    server.request_timeout = milliseconds(*ms);
  if (auto ms = in.integer("write_timeout_ms", 100, 600'000))
    server.write_timeout = milliseconds(*ms);
  if (auto n = in.integer("max_requests_per_s", 0, 1'000'000)) server.max_requests_per_s = int(*n);
  if (auto n = in.integer("max_client_requests_per_s", 0, 1'000'000))
    server.max_client_requests_per_s = int(*n);
  if (auto path = in.string("control_socket")) {
    // sun_path holds 108 bytes with the terminating NUL.
    if (!path->empty() && path->front() != '/')
      in.error("control_socket", fmt::format("\"{}\" is not an absolute path, expected e.g. "
                                             "\"{}\" (or \"\" for none)",
                                             *path, kDefaultControlSocket));
    else if (path->size() > 107)
      in.error("control_socket", fmt::format("the path is {} characters long; a Unix socket's "
                                             "may be at most 107",
                                             path->size()));
    else
      server.control_socket = *path;
  }
  read_state_dir(in, errors.file(), server.state_dir);
  if (auto user = in.string("user")) {
    // A user name as useradd takes it; whether it exists is for the machine that runs it.
    const bool plain = !user->empty() && user->size() <= 32 &&
                       user->find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                               "0123456789_.-") == std::string::npos &&
                       user->front() != '-';
    if (plain)
      server.user = *user;
    else
      in.error("user", fmt::format("\"{}\" is not a user name, expected e.g. \"tiltgate\"", *user));
  }
  in.reject_unknown_keys();
  return server;
}

HttpConfig read_http(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "http", errors);
  HttpConfig http;
  if (auto enabled = in.boolean("enabled")) http.enabled = *enabled;
  if (auto listen = in.string("listen")) {
    if (is_ip_address(*listen))
      http.listen = *listen;
    else
      in.error("listen", fmt::format("\"{}\" is not an IPv4 or IPv6 address, expected e.g. "
                                     "\"127.0.0.1\", \"0.0.0.0\" or \"::\"",
                                     *listen));
  }
  if (auto port = in.integer("port", 1, 65535)) http.port = std::uint16_t(*port);
  if (auto allow = read_allow_list(in, "allow")) {
    http.allow = *allow;
    http.allow_given = true;
  }
  // At most the HTTP server's max_clients (16, http/http_server.h).
  if (auto n = in.integer("max_clients_per_host", 1, 16)) http.max_clients_per_host = int(*n);
  if (auto n = in.integer("max_requests_per_s", 0, 1'000'000)) http.max_requests_per_s = int(*n);
  if (auto n = in.integer("max_client_requests_per_s", 0, 1'000'000))
    http.max_client_requests_per_s = int(*n);
  if (auto seconds = in.integer("history_seconds", 10, 86400))
    http.history_seconds = std::chrono::seconds(*seconds);
  if (auto interval = in.integer("history_interval_ms", 100, 60000))
    http.history_interval = std::chrono::milliseconds(*interval);
  // The ring's size is fixed memory per sensor: bounded so a large plant stays a few MB.
  const auto samples = std::chrono::milliseconds(http.history_seconds).count() /
                       http.history_interval.count();
  if (samples > kMaxHistorySamples)
    in.error(in.has("history_seconds") ? "history_seconds" : "history_interval_ms",
             fmt::format("{} s of history every {} ms is {} samples per sensor, expected at most "
                         "{} (a longer history_interval_ms or shorter history_seconds)",
                         http.history_seconds.count(), http.history_interval.count(), samples,
                         kMaxHistorySamples));
  else if (samples < 2)
    in.error(in.has("history_interval_ms") ? "history_interval_ms" : "history_seconds",
             fmt::format("{} s of history every {} ms is fewer than 2 samples, expected a "
                         "history_interval_ms of at most half of history_seconds",
                         http.history_seconds.count(), http.history_interval.count()));
  read_server_names(in, http);
  read_console_keys(in, http, errors);
  in.reject_unknown_keys();
  return http;
}

ParsedSensor read_sensor(const toml::table& table, std::string path, ErrorList& errors,
                         FamilyList families) {
  TableReader in(table, std::move(path), errors);
  SensorConfig sensor;
  sensor.line = in.located().header().line;
  if (auto name = in.string("name", Presence::required)) {
    check_name(in, "name", *name);
    sensor.name = *name;
  }
  if (auto bus = in.string("bus", Presence::required)) sensor.bus = *bus;
  if (auto model = in.choice("model", model_names(families), Presence::required))
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
  if (auto serial = in.string("serial")) {
    sensor.serial = std::string(trim_whitespace(*serial));
    if (sensor.serial.empty()) in.error("serial", "must not be empty (leave the key out instead)");
  }
  read_family_keys(in, sensor, families, errors);
  read_mounting(in, sensor, errors, families);
  read_baseline(in, sensor, errors, families);
  read_alarms(in, sensor, errors, families);
  read_burst(in, sensor);
  read_offline(in, sensor);
  ParsedSensor parsed{std::move(sensor), address.value_or(0), in.located(), {}, {}};
  read_map_key(in, parsed, errors, families);
  in.reject_unknown_keys();
  parsed.where = in.located();
  return parsed;
}

}  // namespace tiltgate::config
