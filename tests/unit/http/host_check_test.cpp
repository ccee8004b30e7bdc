// http/host_check.h: which Host headers name this gateway (issue 52, item 8: DNS rebinding).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "http/host_check.h"

using namespace tiltgate;

namespace {

const std::vector<std::string> kNames{"gw-3.plant.example", "localhost", "10.0.0.5", "fd00::5"};

HostVerdict check(std::string_view host, std::string_view local = "192.168.7.1") {
  return check_host(host, kNames, local);
}

}  // namespace

TEST_CASE("host check: a server name, with or without its port, in any case, is ours") {
  CHECK(check("gw-3.plant.example") == HostVerdict::ours);
  CHECK(check("gw-3.plant.example:8080") == HostVerdict::ours);
  CHECK(check("GW-3.Plant.Example:443") == HostVerdict::ours);
  CHECK(check("gw-3.plant.example.") == HostVerdict::ours);  // the root's dot
  CHECK(check("localhost:8080") == HostVerdict::ours);
  CHECK(check("10.0.0.5:8080") == HostVerdict::ours);
  CHECK(check("[fd00::5]:8080") == HostVerdict::ours);
  CHECK(check("[fd00:0:0:0:0:0:0:5]") == HostVerdict::ours);  // the same address written out
}

TEST_CASE("host check: another name is not ours, however close (DNS rebinding)") {
  CHECK(check("attacker.example") == HostVerdict::other);
  CHECK(check("attacker.example:8080") == HostVerdict::other);
  CHECK(check("gw-3.plant.example.attacker.example") == HostVerdict::other);
  CHECK(check("plant.example") == HostVerdict::other);
  CHECK(check("localhost.attacker.example") == HostVerdict::other);
  CHECK(check("10.0.0.6") == HostVerdict::other);
  CHECK(check("[fd00::6]") == HostVerdict::other);
  CHECK(check("gw-3.plant.example\r\nX: y") == HostVerdict::other);
}

TEST_CASE("host check: the address the request came in on is ours, whatever the names") {
  CHECK(check("192.168.7.1", "192.168.7.1") == HostVerdict::ours);
  CHECK(check("192.168.7.1:8080", "192.168.7.1") == HostVerdict::ours);
  CHECK(check("192.168.7.1", "::ffff:192.168.7.1") == HostVerdict::ours);  // a dual-stack socket
  CHECK(check("[::1]:8080", "::1") == HostVerdict::ours);
  CHECK(check("192.168.7.2", "192.168.7.1") == HostVerdict::other);
  CHECK(check_host("127.0.0.1:8080", {}, "127.0.0.1") == HostVerdict::ours);
  CHECK(check_host("localhost", {}, "127.0.0.1") == HostVerdict::other);
}

TEST_CASE("host check: no Host, or an empty one, is missing") {
  CHECK(check("") == HostVerdict::missing);
  CHECK(check(":8080") == HostVerdict::missing);
  CHECK(check("[]") == HostVerdict::missing);
}

TEST_CASE("host check: the default names are the listen address, localhost and the machine's") {
  CHECK(default_server_names("127.0.0.1", "gw-3.plant.example") ==
        std::vector<std::string>{"127.0.0.1", "localhost", "gw-3.plant.example", "gw-3"});
  CHECK(default_server_names("0.0.0.0", "gw-3") == std::vector<std::string>{"localhost", "gw-3"});
  CHECK(default_server_names("::", "gw-3") == std::vector<std::string>{"localhost", "gw-3"});
  CHECK(default_server_names("10.0.0.5", "") == std::vector<std::string>{"10.0.0.5", "localhost"});
}
