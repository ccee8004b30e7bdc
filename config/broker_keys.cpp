#include "config/broker_keys.h"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <filesystem>

namespace tiltgate::config {

using toml_input::Presence;
using toml_input::TableReader;

std::string host_name() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0 || name[0] == '\0') return "localhost";
  return name.data();
}

namespace {

void read_file_key(TableReader& in, std::string_view key, std::string& out) {
  auto path = in.string(key);
  if (!path) return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(*path, ec))
    in.error(key, fmt::format("\"{}\" is not a file", *path));
  else
    out = *path;
}

}  // namespace

void read_broker_keys(TableReader& in, bool host_required, BrokerKeys& out) {
  if (auto host = in.string("host", host_required ? Presence::required : Presence::optional)) {
    if (host->empty())
      in.error("host", "empty, expected the broker's host name or IP address");
    else
      out.host = *host;
  }
  if (auto port = in.integer("port", 1, 65535)) out.port = std::uint16_t(*port);
  // libmosquitto refuses a keep-alive under 5 s (mosquitto_connect: MOSQ_ERR_INVAL).
  if (auto keepalive = in.integer("keepalive_s", 5, 65535)) out.keepalive_s = int(*keepalive);
  if (auto username = in.string("username")) out.username = *username;
  if (auto password = in.string("password")) {
    if (!in.has("username"))
      in.error("password", "a password needs a username");
    else
      out.password = *password;
  }
  read_file_key(in, "ca_file", out.ca_file);
  read_file_key(in, "cert_file", out.cert_file);
  read_file_key(in, "key_file", out.key_file);
  if (in.has("cert_file") != in.has("key_file"))
    in.error(in.has("cert_file") ? "cert_file" : "key_file",
             "a client certificate needs both cert_file and key_file");
  if ((in.has("cert_file") || in.has("key_file")) && !in.has("ca_file"))
    in.error(in.has("cert_file") ? "cert_file" : "key_file",
             "a client certificate is sent over TLS only: give ca_file too");
}

}  // namespace tiltgate::config
