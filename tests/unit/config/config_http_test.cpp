// The [http] table: defaults (on, loopback, 8080), each key read, and its mistakes reported
// like [server]'s.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("config: [http] left out serves on loopback port 8080") {
  const Config config = loads(valid_plus(""));
  CHECK(config.http.enabled);
  CHECK(config.http.listen == "127.0.0.1");
  CHECK(config.http.port == 8080);
}

TEST_CASE("config: [http] keys are read") {
  const Config config =
      loads("[http]\nenabled = false\nlisten = \"::\"\nport = 9100\n" + valid_plus(""));
  CHECK_FALSE(config.http.enabled);
  CHECK(config.http.listen == "::");
  CHECK(config.http.port == 9100);
}

TEST_CASE("config: [http] mistakes are reported at their key") {
  expect_error("[http]\nlisten = \"localhost\"\n" + valid_plus(""), 2, "http.listen",
               "\"localhost\" is not an IPv4 or IPv6 address, expected e.g. \"127.0.0.1\", "
               "\"0.0.0.0\" or \"::\"");
  expect_error("[http]\nport = 0\n" + valid_plus(""), 2, "http.port",
               "0 is out of range, expected 1..65535");
  expect_error("[http]\nprot = 80\n" + valid_plus(""), 2, "http.prot",
               "unknown key; did you mean \"port\"?");
  expect_error("http = 8080\n" + valid_plus(""), 1, "http",
               "expected a table ([http]), got an integer");
}

TEST_CASE("config: an unknown table close to [http] suggests it") {
  expect_error(valid_plus("[htp]\nport = 1\n"), 10, "htp", "unknown table; did you mean [http]?");
}

TEST_CASE("config: [http] history keeps 600 s at one sample a second by default") {
  const Config config = loads(valid_plus(""));
  CHECK(config.http.history_seconds == std::chrono::seconds(600));
  CHECK(config.http.history_interval == std::chrono::milliseconds(1000));
}

TEST_CASE("config: [http] history keys are read and bounded to 600 samples per sensor") {
  const Config config =
      loads("[http]\nhistory_seconds = 1200\nhistory_interval_ms = 2000\n" + valid_plus(""));
  CHECK(config.http.history_seconds == std::chrono::seconds(1200));
  CHECK(config.http.history_interval == std::chrono::milliseconds(2000));
  expect_error("[http]\nhistory_seconds = 3600\n" + valid_plus(""), 2, "http.history_seconds",
               "3600 s of history every 1000 ms is 3600 samples per sensor, expected at most 600 "
               "(a longer history_interval_ms or shorter history_seconds)");
  expect_error("[http]\nhistory_interval_ms = 50\n" + valid_plus(""), 2,
               "http.history_interval_ms", "50 is out of range, expected 100..60000");
  expect_error("[http]\nhistory_seconds = 5\n" + valid_plus(""), 2, "http.history_seconds",
               "5 is out of range, expected 10..86400");
  expect_error("[http]\nhistory_seconds = 10\nhistory_interval_ms = 6000\n" + valid_plus(""), 3,
               "http.history_interval_ms",
               "10 s of history every 6000 ms is fewer than 2 samples, expected a "
               "history_interval_ms of at most half of history_seconds");
}

TEST_CASE("config: [http] max_clients_per_host is 8 by default, read, and at most the server's 16") {
  CHECK(loads(valid_plus("")).http.max_clients_per_host == 8);
  CHECK(loads("[http]\nmax_clients_per_host = 2\n" + valid_plus("")).http.max_clients_per_host == 2);
  expect_error("[http]\nmax_clients_per_host = 17\n" + valid_plus(""), 2,
               "http.max_clients_per_host", "17 is out of range, expected 1..16");
  expect_error("[http]\nmax_clients_per_host = 0\n" + valid_plus(""), 2,
               "http.max_clients_per_host", "0 is out of range, expected 1..16");
}

TEST_CASE("config: [http] server_names left out is empty: the HTTP service takes the defaults") {
  CHECK(loads(valid_plus("")).http.server_names.empty());
}

TEST_CASE("config: [http] server_names are read, host names and addresses") {
  const Config config = loads(
      "[http]\nserver_names = [\"gw-3.plant.example\", \"10.0.0.5\", \"fd00::5\", \"gw-3\"]\n" +
      valid_plus(""));
  CHECK(config.http.server_names ==
        std::vector<std::string>{"gw-3.plant.example", "10.0.0.5", "fd00::5", "gw-3"});
}

TEST_CASE("config: [http] server_names mistakes are reported at their key") {
  expect_error("[http]\nserver_names = []\n" + valid_plus(""), 2, "http.server_names",
               "0 names, expected 1 to 32");
  expect_error("[http]\nserver_names = [\"gw-3:8080\"]\n" + valid_plus(""), 2,
               "http.server_names",
               "\"gw-3:8080\" is not a host name or an IP address, expected e.g. "
               "\"gw-3.plant.example\" or \"10.0.0.5\" (no port)");
  expect_error("[http]\nserver_names = [\"*\"]\n" + valid_plus(""), 2, "http.server_names",
               "\"*\" is not a host name or an IP address, expected e.g. "
               "\"gw-3.plant.example\" or \"10.0.0.5\" (no port)");
  expect_error("[http]\nserver_names = [\"gw\\nx\"]\n" + valid_plus(""), 2, "http.server_names",
               "\"gw\\nx\" is not a host name or an IP address, expected e.g. "
               "\"gw-3.plant.example\" or \"10.0.0.5\" (no port)");
  expect_error("[http]\nserver_names = [\"-gw\"]\n" + valid_plus(""), 2, "http.server_names",
               "\"-gw\" is not a host name or an IP address, expected e.g. "
               "\"gw-3.plant.example\" or \"10.0.0.5\" (no port)");
}
