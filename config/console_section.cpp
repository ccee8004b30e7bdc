// [http] users_file, tls_cert_file, tls_key_file, session_idle_seconds and session_max_seconds:
// the web console's keys (docs/web-console.md). The certificate and key are read here, when the
// configuration loads, so a missing one is reported at its line like any other mistake.
#include <fmt/format.h>

#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;

void read_console_keys(TableReader& in, HttpConfig& http, ErrorList& errors) {
  if (auto users = in.string("users_file")) {
    if (users->empty() || users->front() != '/')
      in.error("users_file", fmt::format("\"{}\" is not an absolute path, expected e.g. "
                                         "\"/etc/tiltgate/users\"",
                                         *users));
    else
      http.users_file = *users;
  }
  const bool cert = in.has("tls_cert_file");
  const bool key = in.has("tls_key_file");
  if (cert != key) {
    in.error(cert ? "tls_cert_file" : "tls_key_file",
             "HTTPS needs both tls_cert_file and tls_key_file");
  } else if (cert) {
    std::string cert_file, key_file, cert_pem, key_pem;
    bool ok = read_pem(in, "tls_cert_file", errors, cert_file, cert_pem);
    ok = read_pem(in, "tls_key_file", errors, key_file, key_pem) && ok;
    if (ok) {
      http.tls_cert_file = std::move(cert_file);
      http.tls_key_file = std::move(key_file);
      http.tls_cert_pem = std::move(cert_pem);
      http.tls_key_pem = std::move(key_pem);
    }
  }
  if (auto idle = in.integer("session_idle_seconds", 60, 86400))
    http.session_idle = std::chrono::seconds(*idle);
  if (auto max = in.integer("session_max_seconds", 300, 7 * 86400))
    http.session_max = std::chrono::seconds(*max);
  if (http.session_idle > http.session_max)
    in.error("session_idle_seconds",
             fmt::format("{} s is longer than session_max_seconds ({} s), expected at most that",
                         http.session_idle.count(), http.session_max.count()));
}

}  // namespace tiltgate::config
