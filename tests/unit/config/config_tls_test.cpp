// [server] tls and plain_tcp: the PEM files are read when the configuration loads (relative
// names against the file's folder), and every mistake is reported at its line.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// A folder with the three PEM files (their contents are not checked at load: the server's
// TLS library does that when it starts), removed at the end.
struct PemFolder {
  PemFolder() {
    path = std::filesystem::temp_directory_path() /
           ("tiltgate-tls-config-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    for (const char* name : {"gateway.pem", "gateway.key", "ca.pem"})
      std::ofstream(path / name) << "-----BEGIN " << name << "-----\n";
  }
  ~PemFolder() { std::filesystem::remove_all(path); }
  std::string config_path() const { return (path / "plant.toml").string(); }
  std::filesystem::path path;
};

const std::string kTls =
    "tls = { cert = \"gateway.pem\", key = \"gateway.key\", ca = \"ca.pem\" }\n";

}  // namespace

TEST_CASE("config: [server] tls reads its files against the config file's folder, port 802") {
  const PemFolder folder;
  auto loaded = load_config_string("[server]\n" + kTls + valid_plus(""), folder.config_path(), registered_families());
  REQUIRE(loaded.has_value());
  const ServerConfig& server = loaded->server;
  CHECK(server.plain_tcp);
  REQUIRE(server.tls.has_value());
  CHECK(server.tls->port == 802);
  CHECK(server.tls->cert_file == (folder.path / "gateway.pem").string());
  CHECK(server.tls->cert_pem == "-----BEGIN gateway.pem-----\n");
  CHECK(server.tls->key_pem == "-----BEGIN gateway.key-----\n");
  CHECK(server.tls->ca_pem == "-----BEGIN ca.pem-----\n");
  CHECK_FALSE(loads(valid_plus("")).server.tls.has_value());
}

TEST_CASE("config: [server] tls mistakes are reported at their line") {
  const PemFolder folder;
  const auto error_in = [&](const std::string& text) {
    auto loaded = load_config_string(text + valid_plus(""), folder.config_path(), registered_families());
    REQUIRE_FALSE(loaded.has_value());
    REQUIRE(loaded.error().size() == 1);
    return loaded.error()[0];
  };
  const ConfigError missing = error_in(
      "[server]\ntls = { cert = \"gateway.pem\", key = \"nope.key\", ca = \"ca.pem\" }\n");
  CHECK(missing.line == 2);
  CHECK(missing.key == "server.tls.key");
  CHECK(missing.message.find((folder.path / "nope.key").string() + ": ") == 0);
  const ConfigError no_ca =
      error_in("[server]\ntls = { cert = \"gateway.pem\", key = \"gateway.key\" }\n");
  CHECK(no_ca.key == "server.tls.ca");
  const ConfigError same_port = error_in("[server]\nport = 802\n" + kTls);
  CHECK(same_port.line == 3);
  CHECK(same_port.message ==
        "port 802 is [server] port too: TLS needs its own (802 is Modbus/TCP Security's)");
  const ConfigError typo = error_in(
      "[server]\ntls = { cert = \"gateway.pem\", key = \"gateway.key\", ca = \"ca.pem\", "
      "prot = 8802 }\n");
  CHECK(typo.key == "server.tls.prot");
}

TEST_CASE("config: plain_tcp = false needs tls, and then serves TLS only") {
  expect_error("[server]\nplain_tcp = false\n" + valid_plus(""), 2, "server.plain_tcp",
               "false without [server] tls would serve nothing: add tls = { cert, key, ca } or "
               "leave plain_tcp out");
  const PemFolder folder;
  auto loaded = load_config_string("[server]\nplain_tcp = false\nport = 802\n" + kTls +
                                       valid_plus(""),
                                   folder.config_path(), registered_families());
  REQUIRE(loaded.has_value());
  CHECK_FALSE(loaded->server.plain_tcp);
  CHECK(loaded->server.tls.has_value());
}

TEST_CASE("config: tls_role_access maps certificate roles to read-only or read-write") {
  const PemFolder folder;
  auto loaded = load_config_string(
      "[server]\n" + kTls +
          "tls_role_access = { engineer = \"read-write\", operator = \"read-only\" }\n"
          "tls_no_role_access = \"read-only\"\n" + valid_plus(""),
      folder.config_path(), registered_families());
  REQUIRE(loaded.has_value());
  const TlsRoleAccess& roles = loaded->server.tls_roles;
  CHECK(roles.of("engineer") == ClientAccess::read_write);
  CHECK(roles.of("operator") == ClientAccess::read_only);
  CHECK(roles.of("visitor") == ClientAccess::read_only);  // a role the table does not name
  CHECK(roles.of(std::nullopt) == ClientAccess::read_only);
  CHECK(roles.knows("operator"));
  CHECK_FALSE(roles.knows("visitor"));
  // Without the keys: certificates keep the rights they had before roles were read.
  auto plain = load_config_string("[server]\n" + kTls + valid_plus(""), folder.config_path(),
                                  registered_families());
  REQUIRE(plain.has_value());
  CHECK(plain->server.tls_roles.of(std::nullopt) == ClientAccess::read_write);
  CHECK(plain->server.tls_roles.of("engineer") == ClientAccess::read_only);
}

TEST_CASE("config: tls_role_access mistakes are reported at their line and key") {
  const PemFolder folder;
  const auto error_in = [&](const std::string& text) {
    auto loaded = load_config_string("[server]\n" + kTls + text + valid_plus(""),
                                     folder.config_path(), registered_families());
    REQUIRE_FALSE(loaded.has_value());
    REQUIRE(loaded.error().size() == 1);
    return loaded.error()[0];
  };
  const ConfigError bad_access =
      error_in("tls_role_access = { engineer = \"read-write\", operator = \"readonly\" }\n");
  CHECK(bad_access.line == 3);
  CHECK(bad_access.key == "server.tls_role_access.operator");
  CHECK(bad_access.message == "\"readonly\" is not valid; did you mean \"read-only\"? (expected \"read-only\" or \"read-write\")");
  const ConfigError not_string = error_in("tls_role_access = { engineer = true }\n");
  CHECK(not_string.key == "server.tls_role_access.engineer");
  const ConfigError empty_role = error_in("tls_role_access = { \"\" = \"read-only\" }\n");
  CHECK(empty_role.key == "server.tls_role_access.");
  CHECK(empty_role.message.find("an empty role name") == 0);
  const ConfigError not_table = error_in("tls_role_access = \"read-only\"\n");
  CHECK(not_table.key == "server.tls_role_access");
  const ConfigError no_role = error_in("tls_no_role_access = \"write\"\n");
  CHECK(no_role.line == 3);
  CHECK(no_role.key == "server.tls_no_role_access");
  CHECK(no_role.message == "\"write\" is not valid, expected \"read-only\" or \"read-write\"");
  expect_error("[server]\ntls_no_role_access = \"read-only\"\n" + valid_plus(""), 2,
               "server.tls_no_role_access",
               "without [server] tls no client shows a certificate to take a role from: add tls "
               "= { cert, key, ca } or leave it out");
}
