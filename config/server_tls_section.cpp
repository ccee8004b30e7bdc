// [server] tls = { cert, key, ca, port } and plain_tcp: Modbus/TCP Security's files are read
// here, when the configuration loads, so a missing or unreadable one is reported with the
// file's line like any other mistake, and the server gets their contents.
#include <fmt/format.h>

#include <filesystem>

#include "config/sections.h"
#include "toml/text_file.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;
using toml_input::read_text_file;

namespace {

// The file named at `key`, resolved against the config file's directory, and its contents.
bool read_pem(TableReader& in, std::string_view key, const ErrorList& errors, std::string& path,
              std::string& contents) {
  auto name = in.string(key, Presence::required);
  if (!name) return false;
  if (name->empty()) {
    in.error(key, "empty, expected a PEM file name");
    return false;
  }
  std::filesystem::path file(*name);
  if (file.is_relative()) file = std::filesystem::path(errors.file()).parent_path() / file;
  path = file.string();
  auto text = read_text_file(path);
  if (!text) {
    in.error(key, fmt::format("{}: {}", path, text.error()));
    return false;
  }
  contents = std::move(*text);
  return true;
}

}  // namespace

void read_server_tls(TableReader& in, ServerConfig& server, ErrorList& errors) {
  if (auto plain = in.boolean("plain_tcp")) server.plain_tcp = *plain;
  if (const toml::table* table = in.table("tls")) {
    TableReader sub(*table, in.located().key_path("tls"), errors);
    ServerTlsConfig tls;
    bool ok = read_pem(sub, "cert", errors, tls.cert_file, tls.cert_pem);
    ok = read_pem(sub, "key", errors, tls.key_file, tls.key_pem) && ok;
    ok = read_pem(sub, "ca", errors, tls.ca_file, tls.ca_pem) && ok;
    if (auto port = sub.integer("port", 1, 65535)) tls.port = std::uint16_t(*port);
    sub.reject_unknown_keys();
    if (ok && server.plain_tcp && tls.port == server.port)
      in.error("tls", fmt::format("port {} is [server] port too: TLS needs its own (802 is "
                                  "Modbus/TCP Security's)",
                                  server.port));
    else if (ok)
      server.tls = std::move(tls);
  }
  if (!server.plain_tcp && !in.has("tls"))
    in.error("plain_tcp", "false without [server] tls would serve nothing: add tls = { cert, key, "
                          "ca } or leave plain_tcp out");
}

}  // namespace tiltgate::config
