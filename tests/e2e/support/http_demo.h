// `tiltgate demo` on free Modbus and HTTP ports, started and answering on its HTTP port: what
// the HTTP e2e tests of the demo begin with.
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "e2e/support/gateway_process.h"

namespace tiltgate::test {

struct HttpDemo {
  HttpDemo() { REQUIRE_MESSAGE(process.wait_listening(http_port), process.log()); }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  GatewayProcess process{
      {"demo", "--port", std::to_string(port), "--http-port", std::to_string(http_port),
       "--no-accounts"},
      dir.path()};
};

}  // namespace tiltgate::test
