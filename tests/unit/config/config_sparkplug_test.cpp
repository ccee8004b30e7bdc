// The [sparkplug] table: off without it, on with it (host and group_id required), each key
// read, the hostname defaults, the Sparkplug id rules, and its mistakes reported at their key.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

constexpr std::string_view kTable = "[sparkplug]\nhost = \"b\"\ngroup_id = \"plant\"\n";

}  // namespace

TEST_CASE("config: [sparkplug] left out runs no edge node") {
  CHECK_FALSE(loads(valid_plus("")).sparkplug.enabled);
}

TEST_CASE("config: [sparkplug] with host and group_id runs the edge node with the defaults") {
  const Config config = loads(std::string(kTable) + valid_plus(""));
  const SparkplugConfig& s = config.sparkplug;
  CHECK(s.enabled);
  CHECK(s.host == "b");
  CHECK(s.port == 1883);
  CHECK(s.group_id == "plant");
  CHECK(s.edge_node_id == this_host());
  CHECK(s.client_id == "tiltgate-sparkplug-" + this_host());
  CHECK(s.keepalive_s == 30);
  CHECK(s.state_dir == "/var/lib/tiltgate");
  CHECK(s.on_change_deg == doctest::Approx(0.01));
  CHECK(s.min_interval == std::chrono::milliseconds(100));
  CHECK(s.max_interval == std::chrono::milliseconds(10000));
  CHECK_FALSE(s.primary_host_id);
  CHECK_FALSE(s.commands);
  CHECK(s.buffer_mb == 64);
  CHECK(s.username.empty());
  CHECK(s.ca_file.empty());
}

TEST_CASE("config: [sparkplug] keys are read") {
  const Config config = loads(
      "[sparkplug]\nhost = \"10.0.0.5\"\nport = 1884\ngroup_id = \"north\"\n"
      "edge_node_id = \"gw-7\"\nclient_id = \"spb-7\"\nusername = \"gw\"\npassword = \"pw\"\n"
      "keepalive_s = 5\nstate_dir = \"/srv/tiltgate\"\non_change_deg = 0\n"
      "min_interval_ms = 0\nmax_interval_ms = 2000\nprimary_host_id = \"scada\"\n"
      "commands = true\nbuffer_mb = 0.05\n" +
      valid_plus(""));
  const SparkplugConfig& s = config.sparkplug;
  CHECK(s.port == 1884);
  CHECK(s.group_id == "north");
  CHECK(s.edge_node_id == "gw-7");
  CHECK(s.client_id == "spb-7");
  CHECK(s.username == "gw");
  CHECK(s.password == "pw");
  CHECK(s.keepalive_s == 5);
  CHECK(s.state_dir == "/srv/tiltgate");
  CHECK(s.on_change_deg == 0.0);
  CHECK(s.min_interval == std::chrono::milliseconds(0));
  CHECK(s.max_interval == std::chrono::milliseconds(2000));
  CHECK(s.primary_host_id == std::optional<std::string>("scada"));
  CHECK(s.commands);
  CHECK(s.buffer_mb == 0.05);
}

TEST_CASE("config: [sparkplug] the default client id follows edge_node_id") {
  const Config config = loads(std::string(kTable) + "edge_node_id = \"gw-9\"\n" + valid_plus(""));
  CHECK(config.sparkplug.client_id == "tiltgate-sparkplug-gw-9");
}

TEST_CASE("config: [sparkplug] a relative state_dir is taken from the file's directory") {
  ScratchDir dir;
  const std::string path =
      dir.write("gw.toml", std::string(kTable) + "state_dir = \"state\"\n" + valid_plus(""));
  auto loaded = load_config_file(path, registered_families());
  REQUIRE(loaded.has_value());
  CHECK(loaded->sparkplug.state_dir ==
        (std::filesystem::path(path).parent_path() / "state").string());
}

TEST_CASE("config: [sparkplug] and [mqtt] run together") {
  const Config config =
      loads(std::string(kTable) + "[mqtt]\nhost = \"b\"\n" + valid_plus(""));
  CHECK(config.sparkplug.enabled);
  CHECK(config.mqtt.enabled);
  CHECK(config.mqtt.client_id != config.sparkplug.client_id);
}

TEST_CASE("config: [sparkplug] ids follow the Sparkplug topic rules") {
  expect_error("[sparkplug]\nhost = \"b\"\ngroup_id = \"a/b\"\n" + valid_plus(""), 3,
               "sparkplug.group_id",
               "group_id \"a/b\" has '+', '#' or '/', which Sparkplug reserves; expected a "
               "Sparkplug id: UTF-8 text without '+', '#' and '/'");
  expect_error(std::string(kTable) + "edge_node_id = \"gw+1\"\n" + valid_plus(""), 4,
               "sparkplug.edge_node_id",
               "edge_node_id \"gw+1\" has '+', '#' or '/', which Sparkplug reserves; expected a "
               "Sparkplug id: UTF-8 text without '+', '#' and '/'");
  expect_error(std::string(kTable) + "primary_host_id = \"\"\n" + valid_plus(""), 4,
               "sparkplug.primary_host_id",
               "primary_host_id is empty; expected a Sparkplug id: UTF-8 text without '+', '#' "
               "and '/'");
}

TEST_CASE("config: [sparkplug] mistakes are reported at their key") {
  expect_error("[sparkplug]\nhost = \"b\"\n" + valid_plus(""), 1, "sparkplug.group_id",
               "required key is missing; expected a string");
  expect_error("[sparkplug]\ngroup_id = \"g\"\n" + valid_plus(""), 1, "sparkplug.host",
               "required key is missing; expected a string");
  expect_error(std::string(kTable) + "port = 0\n" + valid_plus(""), 4, "sparkplug.port",
               "0 is out of range, expected 1..65535");
  expect_error(std::string(kTable) + "keepalive_s = 1\n" + valid_plus(""), 4,
               "sparkplug.keepalive_s", "1 is out of range, expected 5..65535");
  expect_error(std::string(kTable) + "state_dir = \"\"\n" + valid_plus(""), 4,
               "sparkplug.state_dir",
               "empty, expected a directory the gateway may write, e.g. \"/var/lib/tiltgate\"");
  expect_error(std::string(kTable) + "min_interval_ms = 5000\nmax_interval_ms = 1000\n" +
                   valid_plus(""),
               4, "sparkplug.min_interval_ms",
               "min_interval_ms (5000) is above max_interval_ms (1000)");
  expect_error(std::string(kTable) + "buffer_mb = 0\n" + valid_plus(""), 4, "sparkplug.buffer_mb",
               "0 is out of range, expected 0.01..65536");
  expect_error(std::string(kTable) + "commands = \"yes\"\n" + valid_plus(""), 4,
               "sparkplug.commands", "expected a boolean, got a string");
  expect_error(std::string(kTable) + "password = \"p\"\n" + valid_plus(""), 4,
               "sparkplug.password", "a password needs a username");
  expect_error(std::string(kTable) + "grup_id = \"x\"\n" + valid_plus(""), 4, "sparkplug.grup_id",
               "unknown key; did you mean \"group_id\"?");
  expect_error("sparkplug = 1\n" + valid_plus(""), 1, "sparkplug",
               "expected a table ([sparkplug]), got an integer");
}

TEST_CASE("config: [sparkplug] and [mqtt] may not share a client id on one broker") {
  expect_error(std::string(kTable) +
                   "client_id = \"gw\"\n[mqtt]\nhost = \"b\"\nclient_id = \"gw\"\n" +
                   valid_plus(""),
               1, "sparkplug.client_id",
               "\"gw\" is [mqtt]'s client_id on the same broker, expected another: the broker "
               "would disconnect one client for the other");
}
