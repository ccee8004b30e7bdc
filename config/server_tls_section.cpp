// [server] tls = { cert, key, ca, port } and plain_tcp: Modbus/TCP Security's files are read
// here, when the configuration loads, so a missing or unreadable one is reported with the
// file's line like any other mistake, and the server gets their contents. tls_role_access and
// tls_no_role_access: its authorization step, a certificate's role to read-only or read-write.
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

namespace {

constexpr std::string_view kReadOnly = "read-only";
constexpr std::string_view kReadWrite = "read-write";

ClientAccess access_named(std::string_view name) {
  return name == kReadOnly ? ClientAccess::read_only : ClientAccess::read_write;
}

// tls_role_access = { engineer = "read-write", operator = "read-only" } and
// tls_no_role_access = "read-write"; both only with tls, where certificates are.
void read_role_access(TableReader& in, ServerConfig& server, ErrorList& errors) {
  if (auto access = in.choice("tls_no_role_access", {kReadOnly, kReadWrite}))
    server.tls_roles.no_role = access_named(*access);
  if (const toml::table* table = in.table("tls_role_access")) {
    TableReader roles(*table, in.located().key_path("tls_role_access"), errors);
    for (const auto& [key, value] : *table) {
      const std::string role(key.str());
      if (role.empty()) {
        roles.error(role, "an empty role name: a certificate's role extension names one");
        continue;
      }
      if (auto access = roles.choice(role, {kReadOnly, kReadWrite}))
        server.tls_roles.roles[role] = access_named(*access);
    }
  }
  for (const std::string_view key : {"tls_role_access", "tls_no_role_access"}) {
    if (in.has(key) && !in.has("tls"))
      in.error(key, "without [server] tls no client shows a certificate to take a role from: "
                    "add tls = { cert, key, ca } or leave it out");
  }
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
  read_role_access(in, server, errors);
  if (!server.plain_tcp && !in.has("tls"))
    in.error("plain_tcp", "false without [server] tls would serve nothing: add tls = { cert, key, "
                          "ca } or leave plain_tcp out");
}

}  // namespace tiltgate::config
