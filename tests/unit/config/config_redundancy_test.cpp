// The [redundancy] table: no standby without it; role and peer required with it, takeover_ms
// and failback defaulted; a peer written HOST:PORT or [IPV6]:PORT; each mistake at its key; and
// takeover_ms at least twice the shortest poll of every bus the standby listens to.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

// Lines 1..3: [redundancy], a role and a peer; `more` from line 4 on, then the valid base.
std::string redundancy_plus(std::string_view more, std::string_view role = "primary") {
  return "[redundancy]\nrole = \"" + std::string(role) + "\"\npeer = \"10.0.0.12:502\"\n" +
         std::string(more) + valid_plus("");
}

// [redundancy] with `peer` as written (line 3), and the valid base.
std::string with_peer(std::string_view peer) {
  return "[redundancy]\nrole = \"standby\"\npeer = \"" + std::string(peer) + "\"\n" +
         valid_plus("");
}

constexpr std::string_view kPeerForm =
    "expected the other gateway's Modbus TCP address as \"HOST:PORT\", e.g. \"10.0.0.12:502\", "
    "\"gw-b.plant.example:502\" or \"[fd00::12]:502\"";

std::string peer_error(std::string_view what) {
  return std::string(what) + "; " + std::string(kPeerForm);
}

// The valid base with its sensor polled every `poll_ms`, then `more`.
std::string polled_every(int poll_ms, std::string_view more = "") {
  return valid_plus("poll_ms = " + std::to_string(poll_ms) + "\n" + std::string(more));
}

}  // namespace

TEST_CASE("config: without [redundancy] the gateway is no half of a pair") {
  const Config config = loads(valid_plus(""));
  CHECK(config.redundancy.role == RedundancyConfig::Role::none);
  CHECK_FALSE(config.redundancy.enabled());
}

TEST_CASE("config: [redundancy] with a role and a peer takes the defaults") {
  const Config config = loads(redundancy_plus(""));
  const RedundancyConfig& r = config.redundancy;
  CHECK(r.enabled());
  CHECK(r.role == RedundancyConfig::Role::primary);
  CHECK(r.peer_host == "10.0.0.12");
  CHECK(r.peer_port == 502);
  CHECK(r.takeover == 2000ms);
  CHECK_FALSE(r.failback);
}

TEST_CASE("config: [redundancy] keys are read") {
  const Config config =
      loads(redundancy_plus("takeover_ms = 5000\nfailback = true\n", "standby"));
  const RedundancyConfig& r = config.redundancy;
  CHECK(r.role == RedundancyConfig::Role::standby);
  CHECK(r.takeover == 5000ms);
  CHECK(r.failback);
}

TEST_CASE("config: a peer is a host name, an IPv4 address or an IPv6 address in brackets") {
  const RedundancyConfig named = loads(with_peer("gw-b.plant.example:1502")).redundancy;
  CHECK(named.peer_host == "gw-b.plant.example");
  CHECK(named.peer_port == 1502);
  const RedundancyConfig loopback = loads(with_peer("[::1]:502")).redundancy;
  CHECK(loopback.peer_host == "::1");
  CHECK(loopback.peer_port == 502);
  const RedundancyConfig zoned = loads(with_peer("[fe80::12%eth0]:65535")).redundancy;
  CHECK(zoned.peer_host == "fe80::12%eth0");
  CHECK(zoned.peer_port == 65535);
}

TEST_CASE("config: [redundancy] needs a role, primary or standby") {
  expect_error("[redundancy]\npeer = \"10.0.0.12:502\"\n" + valid_plus(""), 1, "redundancy.role",
               "required key is missing; expected \"primary\" or \"standby\"");
  expect_error(redundancy_plus("", "primery"), 2, "redundancy.role",
               "\"primery\" is not valid; did you mean \"primary\"? (expected \"primary\" or "
               "\"standby\")");
  expect_error(redundancy_plus("", "master"), 2, "redundancy.role",
               "\"master\" is not valid, expected \"primary\" or \"standby\"");
}

TEST_CASE("config: [redundancy] needs the peer's address, with its port") {
  expect_error("[redundancy]\nrole = \"standby\"\n" + valid_plus(""), 1, "redundancy.peer",
               peer_error("required key is missing"));
  expect_error(with_peer("10.0.0.12"), 3, "redundancy.peer",
               peer_error("\"10.0.0.12\" has no port"));
  expect_error(with_peer("[fd00::12]"), 3, "redundancy.peer",
               peer_error("\"[fd00::12]\" has no port"));
  expect_error(with_peer(""), 3, "redundancy.peer", "empty, " + std::string(kPeerForm));
}

TEST_CASE("config: a peer's port is 1..65535") {
  expect_error(with_peer("10.0.0.12:0"), 3, "redundancy.peer",
               "the port 0 is out of range, expected 1..65535");
  expect_error(with_peer("10.0.0.12:65536"), 3, "redundancy.peer",
               "the port 65536 is out of range, expected 1..65535");
  expect_error(with_peer("gw-b:modbus"), 3, "redundancy.peer",
               "the port \"modbus\" is not a number, expected 1..65535");
  expect_error(with_peer("gw-b:"), 3, "redundancy.peer",
               "the port \"\" is not a number, expected 1..65535");
}

TEST_CASE("config: a peer written another way says how to write it") {
  expect_error(with_peer("fd00::12:502"), 3, "redundancy.peer",
               peer_error("\"fd00::12:502\": an IPv6 address is written in brackets, before its "
                          "port"));
  expect_error(with_peer("[fd00::12:502"), 3, "redundancy.peer",
               peer_error("\"[fd00::12:502\": an IPv6 address needs its closing ']'"));
  expect_error(with_peer("[10.0.0.12]:502"), 3, "redundancy.peer",
               peer_error("\"[10.0.0.12]:502\": \"10.0.0.12\" in brackets is not an IPv6 address"));
  expect_error(with_peer("[::1]502"), 3, "redundancy.peer",
               peer_error("\"[::1]502\": unexpected \"502\" after the host"));
  expect_error(with_peer("tcp://10.0.0.12:502"), 3, "redundancy.peer",
               peer_error("\"tcp://10.0.0.12:502\" has a scheme"));
  expect_error(with_peer(":502"), 3, "redundancy.peer", peer_error("\":502\" has no host"));
  expect_error(with_peer("gw_b:502"), 3, "redundancy.peer",
               peer_error("\"gw_b:502\": \"gw_b\" is not a host name or an IP address"));
}

TEST_CASE("config: takeover_ms is 200..60000 and failback a boolean") {
  expect_error(redundancy_plus("takeover_ms = 2\n"), 4, "redundancy.takeover_ms",
               "2 is out of range, expected 200..60000");
  expect_error(redundancy_plus("takeover_ms = 60001\n"), 4, "redundancy.takeover_ms",
               "60001 is out of range, expected 200..60000");
  expect_error(redundancy_plus("failback = \"yes\"\n"), 4, "redundancy.failback",
               "expected a boolean, got a string");
}

TEST_CASE("config: an unknown [redundancy] key or a misspelt table gets the close name") {
  expect_error(redundancy_plus("takeover = 3000\n"), 4, "redundancy.takeover",
               "unknown key; did you mean \"takeover_ms\"?");
  expect_error(redundancy_plus("colour = \"red\"\n"), 4, "redundancy.colour",
               "unknown key; expected one of: role, peer, takeover_ms, failback");
  expect_error("[redundancey]\nrole = \"primary\"\n" + valid_plus(""), 1, "redundancey",
               "unknown table; did you mean [redundancy]?");
  expect_error("redundancy = \"primary\"\n" + valid_plus(""), 1, "redundancy",
               "expected a table ([redundancy]), got a string");
}

TEST_CASE("config: takeover_ms shorter than twice a bus's shortest poll is refused") {
  // Lines 1..3 [redundancy], then the bus from line 4 and its sensor's poll_ms on line 13.
  expect_error("[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\n" + polled_every(1500), 1,
               "redundancy.takeover_ms",
               "2000 ms (the default) is less than twice the shortest poll_ms on bus \"line1\" "
               "(1500 ms, sensor \"boom\"): a live primary leaves that line quiet for up to a "
               "poll period between requests, and the standby would take the lines over from it. "
               "Raise takeover_ms to at least 3000, or poll a sensor of bus \"line1\" every 1000 "
               "ms or less");
  expect_error("[redundancy]\nrole = \"primary\"\npeer = \"gw-b:502\"\ntakeover_ms = 250\n" +
                   polled_every(150),
               4, "redundancy.takeover_ms",
               "250 ms is less than twice the shortest poll_ms on bus \"line1\" (150 ms, sensor "
               "\"boom\"): a live primary leaves that line quiet for up to a poll period between "
               "requests, and the standby would take the lines over from it. Raise takeover_ms "
               "to at least 300, or poll a sensor of bus \"line1\" every 125 ms or less");
}

TEST_CASE("config: takeover_ms of twice the shortest poll, or more, is taken") {
  loads("[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\n" + polled_every(1000));
  loads("[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\ntakeover_ms = 3000\n" +
        polled_every(1500));
  // The bus's fastest sensor sets its pace: a slow one beside it leaves no long gap.
  loads("[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\n" +
        polled_every(10000, sensor_text("jib", "line1", 224, 2) + "poll_ms = 1000\n"));
  // Without [redundancy], slow polls are nobody's business.
  loads(polled_every(60000));
}

TEST_CASE("config: each bus the standby listens to is checked, one error a bus") {
  const std::string second_bus =
      "[[bus]]\nname = \"line2\"\nport = \"/dev/ttyUSB1\"\n" + sensor_text("jib", "line2", 1, 2) +
      "poll_ms = 5000\n";
  const ConfigError e = only_error("[redundancy]\nrole = \"primary\"\npeer = \"gw-b:502\"\n" +
                                   valid_plus(second_bus));
  CHECK(e.key == "redundancy.takeover_ms");
  CHECK(e.message.find("on bus \"line2\" (5000 ms, sensor \"jib\")") != std::string::npos);
  CHECK(e.message.find("Raise takeover_ms to at least 10000") != std::string::npos);
}

TEST_CASE("config: a bus behind a device server is not held to the standby's takeover_ms") {
  // The standby cannot listen to it, so its quiet decides nothing (a warning says so).
  std::string text = "[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\n" + polled_every(5000);
  text.replace(text.find("/dev/ttyUSB0"), 12, "tcp://192.168.1.20:4001");
  CHECK(loads(text).redundancy.enabled());
}
