// The [mqtt] table: off without it, on with it (host required), each key read, the hostname
// defaults, and its mistakes reported like every other table's.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("config: [mqtt] left out publishes nothing") {
  CHECK_FALSE(loads(valid_plus("")).mqtt.enabled);
}

TEST_CASE("config: [mqtt] with a host publishes with the defaults") {
  const Config config = loads("[mqtt]\nhost = \"broker.plant\"\n" + valid_plus(""));
  CHECK(config.mqtt.enabled);
  CHECK(config.mqtt.host == "broker.plant");
  CHECK(config.mqtt.port == 1883);
  CHECK(config.mqtt.client_id == "tiltgate-" + this_host());
  CHECK(config.mqtt.topic_prefix == "tiltgate/" + this_host());
  CHECK(config.mqtt.qos == 1);
  CHECK(config.mqtt.interval == std::chrono::milliseconds(1000));
  CHECK(config.mqtt.on_change_deg == doctest::Approx(0.01));
  CHECK(config.mqtt.keepalive_s == 30);
  CHECK_FALSE(config.mqtt.backlog.has_value());  // buffer_mb alone bounds it
  CHECK(config.mqtt.state_dir == "/var/lib/tiltgate");
  CHECK(config.mqtt.buffer_mb == 64);
  CHECK(config.mqtt.username.empty());
  CHECK(config.mqtt.ca_file.empty());
}

TEST_CASE("config: [mqtt] keys are read") {
  const Config config = loads(
      "[mqtt]\nhost = \"10.0.0.5\"\nport = 1884\nclient_id = \"gw-7\"\n"
      "topic_prefix = \"plant/north/gw-7\"\nqos = 2\ninterval_ms = 250\non_change_deg = 0\n"
      "keepalive_s = 5\nusername = \"gw\"\npassword = \"secret\"\nbacklog = 0\n" +
      valid_plus(""));
  CHECK(config.mqtt.port == 1884);
  CHECK(config.mqtt.client_id == "gw-7");
  CHECK(config.mqtt.topic_prefix == "plant/north/gw-7");
  CHECK(config.mqtt.qos == 2);
  CHECK(config.mqtt.interval == std::chrono::milliseconds(250));
  CHECK(config.mqtt.on_change_deg == 0.0);
  CHECK(config.mqtt.keepalive_s == 5);
  CHECK(config.mqtt.username == "gw");
  CHECK(config.mqtt.password == "secret");
  CHECK(config.mqtt.backlog == 0);
}

TEST_CASE("config: [mqtt] state_dir, buffer_mb and backlog say where and how much is kept") {
  ScratchDir dir;
  const Config config =
      loads("[mqtt]\nhost = \"b\"\nstate_dir = \"" + dir.path("state") +
            "\"\nbuffer_mb = 0.5\nbacklog = 5000\n" + valid_plus(""));
  CHECK(config.mqtt.state_dir == dir.path("state"));
  CHECK(config.mqtt.buffer_mb == doctest::Approx(0.5));
  CHECK(config.mqtt.backlog == std::size_t{5000});
  // Checking creates nothing: `tiltgate check` leaves the disk as it was.
  CHECK_FALSE(std::filesystem::exists(dir.path("state")));
}

TEST_CASE("config: [mqtt] a relative state_dir is taken from the file's directory") {
  ScratchDir dir;
  const std::string file =
      dir.write("tiltgate.toml", "[mqtt]\nhost = \"b\"\nstate_dir = \"state\"\n" + valid_plus(""));
  auto loaded = load_config_file(file, registered_families());
  REQUIRE(loaded);
  CHECK(loaded->mqtt.state_dir == (std::filesystem::path(file).parent_path() / "state").string());
}

TEST_CASE("config: [mqtt] state_dir and buffer_mb mistakes are reported at their key") {
  expect_error("[mqtt]\nhost = \"b\"\nstate_dir = \"\"\n" + valid_plus(""), 3, "mqtt.state_dir",
               "empty, expected a directory the gateway may write, e.g. \"/var/lib/tiltgate\"");
  expect_error("[mqtt]\nhost = \"b\"\nbuffer_mb = 0\n" + valid_plus(""), 3, "mqtt.buffer_mb",
               "0 is out of range, expected 0.01..65536");
}

TEST_CASE("config: [mqtt] enabled = false keeps the table but publishes nothing") {
  const Config config = loads("[mqtt]\nenabled = false\n" + valid_plus(""));
  CHECK_FALSE(config.mqtt.enabled);
}

TEST_CASE("config: [mqtt] TLS files are read when they exist") {
  ScratchDir dir;
  const std::string ca = dir.write("ca.crt", "x");
  const std::string cert = dir.write("gw.crt", "x");
  const std::string key = dir.write("gw.key", "x");
  const Config config = loads("[mqtt]\nhost = \"b\"\nca_file = \"" + ca + "\"\ncert_file = \"" +
                              cert + "\"\nkey_file = \"" + key + "\"\n" + valid_plus(""));
  CHECK(config.mqtt.ca_file == ca);
  CHECK(config.mqtt.cert_file == cert);
  CHECK(config.mqtt.key_file == key);
}

TEST_CASE("config: [mqtt] mistakes are reported at their key") {
  expect_error("[mqtt]\nport = 1884\n" + valid_plus(""), 1, "mqtt.host",
               "required key is missing; expected a string");
  expect_error("[mqtt]\nhost = \"\"\n" + valid_plus(""), 2, "mqtt.host",
               "empty, expected the broker's host name or IP address");
  expect_error("[mqtt]\nhost = \"b\"\nqos = 3\n" + valid_plus(""), 3, "mqtt.qos",
               "3 is out of range, expected 0..2");
  expect_error("[mqtt]\nhost = \"b\"\ninterval_ms = 10\n" + valid_plus(""), 3, "mqtt.interval_ms",
               "10 is out of range, expected 100..3600000");
  expect_error("[mqtt]\nhost = \"b\"\non_change_deg = -1\n" + valid_plus(""), 3,
               "mqtt.on_change_deg", "-1 is out of range, expected 0..360");
  expect_error("[mqtt]\nhost = \"b\"\nkeepalive_s = 2\n" + valid_plus(""), 3, "mqtt.keepalive_s",
               "2 is out of range, expected 5..65535");
  expect_error("[mqtt]\nhost = \"b\"\nbacklog = -1\n" + valid_plus(""), 3, "mqtt.backlog",
               "-1 is out of range, expected 0..100000000");
  expect_error("[mqtt]\nhost = \"b\"\nclient_id = \"\"\n" + valid_plus(""), 3, "mqtt.client_id",
               "empty, expected a name unique among the broker's clients");
  expect_error("[mqtt]\nhost = \"b\"\npassword = \"p\"\n" + valid_plus(""), 3, "mqtt.password",
               "a password needs a username");
  expect_error("[mqtt]\nhost = \"b\"\nca_file = \"/nonexistent/ca.crt\"\n" + valid_plus(""), 3,
               "mqtt.ca_file", "\"/nonexistent/ca.crt\" is not a file");
  expect_error("[mqtt]\nhost = \"b\"\nhots = \"c\"\n" + valid_plus(""), 3, "mqtt.hots",
               "unknown key; did you mean \"host\"?");
  expect_error("mqtt = \"broker\"\n" + valid_plus(""), 1, "mqtt",
               "expected a table ([mqtt]), got a string");
}

TEST_CASE("config: [mqtt] topic_prefix must be a plain topic") {
  for (const char* prefix : {"plant/#", "plant/+/gw", "/plant", "plant/", "plant//gw", ""}) {
    CAPTURE(prefix);
    expect_error("[mqtt]\nhost = \"b\"\ntopic_prefix = \"" + std::string(prefix) + "\"\n" +
                     valid_plus(""),
                 3, "mqtt.topic_prefix",
                 "\"" + std::string(prefix) +
                     "\" is not a topic prefix, expected levels separated by '/' with no empty "
                     "level and no '+' or '#', e.g. \"plant/line1\"");
  }
}

TEST_CASE("config: a client certificate needs its key and a CA file") {
  ScratchDir dir;
  const std::string cert = dir.write("gw.crt", "x");
  const std::string key = dir.write("gw.key", "x");
  expect_error("[mqtt]\nhost = \"b\"\ncert_file = \"" + cert + "\"\nca_file = \"" + cert + "\"\n" +
                   valid_plus(""),
               3, "mqtt.cert_file", "a client certificate needs both cert_file and key_file");
  expect_error("[mqtt]\nhost = \"b\"\ncert_file = \"" + cert + "\"\nkey_file = \"" + key + "\"\n" +
                   valid_plus(""),
               3, "mqtt.cert_file", "a client certificate is sent over TLS only: give ca_file too");
}

TEST_CASE("config: [server] state_dir is where the audit trail is kept and the feeds' default, their own key winning") {
  CHECK(loads(valid_plus("")).server.state_dir == "/var/lib/tiltgate");
  ScratchDir dir;
  const std::string file = dir.write(
      "tiltgate.toml", "[server]\nstate_dir = \"state\"\n[mqtt]\nhost = \"b\"\n"
                       "[sparkplug]\nhost = \"b\"\ngroup_id = \"plant\"\n" + valid_plus(""));
  auto loaded = load_config_file(file, registered_families());
  REQUIRE(loaded);
  const std::string state = (std::filesystem::path(file).parent_path() / "state").string();
  CHECK(loaded->server.state_dir == state);
  CHECK(loaded->mqtt.state_dir == state);
  CHECK(loaded->sparkplug.state_dir == state);
  // Their own key wins, whichever table comes first in the file.
  const Config own = loads("[mqtt]\nhost = \"b\"\nstate_dir = \"/srv/mqtt\"\n"
                           "[server]\nstate_dir = \"/srv/tiltgate\"\n" + valid_plus(""));
  CHECK(own.server.state_dir == "/srv/tiltgate");
  CHECK(own.mqtt.state_dir == "/srv/mqtt");
  CHECK(own.sparkplug.state_dir == "/srv/tiltgate");
  expect_error("[server]\nstate_dir = \"\"\n" + valid_plus(""), 2, "server.state_dir",
               "empty, expected a directory the gateway may write, e.g. \"/var/lib/tiltgate\"");
}
