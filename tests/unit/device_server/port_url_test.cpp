#include "device_server/port_url.h"

#include <doctest/doctest.h>

namespace tiltgate {

TEST_CASE("a port that is not written as a URL is a tty path") {
  const auto port = parse_port("/dev/serial/by-id/usb-FTDI_FT232R-if00-port0");
  REQUIRE(port);
  CHECK(port->scheme == PortScheme::tty);
  CHECK(port->path == "/dev/serial/by-id/usb-FTDI_FT232R-if00-port0");
  CHECK_FALSE(port->over_network());
}

TEST_CASE("tcp and rfc2217 URLs give the scheme, host and port") {
  const auto raw = parse_port("tcp://192.168.1.20:4001");
  REQUIRE(raw);
  CHECK(raw->scheme == PortScheme::tcp);
  CHECK(raw->host == "192.168.1.20");
  CHECK(raw->port == 4001);
  CHECK(raw->endpoint() == "192.168.1.20:4001");
  const auto telnet = parse_port("rfc2217://nport-hall-3.plant.local:950");
  REQUIRE(telnet);
  CHECK(telnet->scheme == PortScheme::rfc2217);
  CHECK(telnet->host == "nport-hall-3.plant.local");
  CHECK(telnet->port == 950);
  const auto v6 = parse_port("tcp://[fd00::20]:4001");
  REQUIRE(v6);
  CHECK(v6->host == "fd00::20");
  CHECK(v6->endpoint() == "[fd00::20]:4001");
}

TEST_CASE("a bad device server URL says what is wrong") {
  auto error_of = [](std::string_view text) {
    const auto port = parse_port(text);
    REQUIRE_FALSE(port);
    return port.error();
  };
  CHECK(error_of("telnet://host:23").find("unknown scheme \"telnet://\"") != std::string::npos);
  CHECK(error_of("tcp://:4001").find("no host") != std::string::npos);
  CHECK(error_of("tcp://host").find("no port") != std::string::npos);
  CHECK(error_of("tcp://host:").find("not a number") != std::string::npos);
  CHECK(error_of("tcp://host:0").find("out of range") != std::string::npos);
  CHECK(error_of("tcp://host:65536").find("out of range") != std::string::npos);
  CHECK(error_of("tcp://host:99999999999").find("out of range") != std::string::npos);
  CHECK(error_of("tcp://host:4001/x").find("unexpected \"/x\"") != std::string::npos);
  CHECK(error_of("tcp://ho st:4001").find("not a host name") != std::string::npos);
  CHECK(error_of("tcp://[fd00::1:4001").find("closing ']'") != std::string::npos);
  CHECK(error_of("").find("empty") != std::string::npos);
}

}  // namespace tiltgate
