// [server] allow and write_allow, [http] allow: read, defaulted, and their mistakes reported at
// the key's line.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("config: without allow lists every address may connect and write, HTTP too") {
  const Config config = loads(valid_plus(""));
  CHECK(config.server.allow.allows_everyone());
  CHECK(config.server.write_allow.allows_everyone());
  CHECK(config.http.allow.allows_everyone());
  CHECK(config.server.max_clients_per_host == 8);
}

TEST_CASE("config: write_allow and [http] allow default to [server] allow") {
  const Config config =
      loads("[server]\nallow = [\"10.0.0.0/8\", \"192.168.1.20\", \"::1\"]\n" + valid_plus(""));
  CHECK(config.server.allow.entries() ==
        std::vector<std::string>{"10.0.0.0/8", "192.168.1.20", "::1"});
  CHECK(config.server.write_allow.entries() == config.server.allow.entries());
  CHECK(config.http.allow.entries() == config.server.allow.entries());
  CHECK(config.server.allow.allows("10.1.2.3"));
  CHECK_FALSE(config.server.allow.allows("192.168.1.21"));
}

TEST_CASE("config: write_allow and [http] allow are read on their own") {
  const Config config = loads(
      "[server]\nallow = [\"10.0.0.0/8\"]\nwrite_allow = [\"10.0.0.5\"]\nmax_clients_per_host = 2\n"
      "[http]\nallow = [\"127.0.0.1\", \"::1\"]\n" +
      valid_plus(""));
  CHECK(config.server.write_allow.entries() == std::vector<std::string>{"10.0.0.5"});
  CHECK(config.http.allow.entries() == std::vector<std::string>{"127.0.0.1", "::1"});
  CHECK(config.server.max_clients_per_host == 2);
  // An empty write_allow: nobody writes.
  const Config readers = loads("[server]\nwrite_allow = []\n" + valid_plus(""));
  CHECK(readers.server.allow.allows_everyone());
  CHECK_FALSE(readers.server.write_allow.allows("10.0.0.5"));
}

TEST_CASE("config: a malformed allow entry is an error at its line") {
  expect_error("[server]\nallow = [\"10.0.0.0/8\", \"10.0.0.300\"]\n" + valid_plus(""), 2,
               "server.allow",
               "\"10.0.0.300\": \"10.0.0.300\" is not an IPv4 or IPv6 address, expected "
               "addresses or networks such as \"192.168.1.20\", \"10.0.0.0/8\" or \"::1\"");
  expect_error("[server]\nport = 502\nwrite_allow = [\"10.0.0.0/40\"]\n" + valid_plus(""), 3,
               "server.write_allow",
               "\"10.0.0.0/40\": the prefix length must be 0..32, expected addresses or networks "
               "such as \"192.168.1.20\", \"10.0.0.0/8\" or \"::1\"");
  expect_error("[http]\nallow = \"127.0.0.1\"\n" + valid_plus(""), 2, "http.allow",
               "expected an array, got a string");
  expect_error("[server]\nallow = []\n" + valid_plus(""), 2, "server.allow",
               "empty: no client could connect (leave allow out to allow every address)");
  expect_error("[server]\nmax_clients_per_host = 0\n" + valid_plus(""), 2,
               "server.max_clients_per_host", "0 is out of range, expected 1..1024");
}
