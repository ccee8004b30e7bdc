// The [http] table: defaults (on, loopback, 8080), each key read, and its mistakes reported
// like [server]'s.
#include <doctest/doctest.h>

#include <string>

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
