// The Modbus TCP server with a unit passed through (the fake handler's unit 9 echoes every
// PDU): any function reaches the handler unchecked once the MBAP header is valid, the reply
// keeps the request's header, and other units keep the server's own checks.
#include <doctest/doctest.h>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("a passed-through unit gets any function, unchecked, with its MBAP header kept") {
  RunningServer server;
  RawSocket raw(server.port);
  // 08 diagnostics, 11 report server id and a read of 0 registers: the server's own parser
  // would refuse each of them.
  raw.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x09, 0x08, 0x00, 0x00, 0xA5, 0x37});
  CHECK(raw.receive(12) == Bytes{0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x09, 0x08, 0x00, 0x00,
                                 0xA5, 0x37});
  raw.send({0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x09, 0x11});
  CHECK(raw.receive(8) == Bytes{0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x09, 0x11});
  raw.send({0x00, 0x03, 0x00, 0x00, 0x00, 0x06, 0x09, 0x03, 0x00, 0x00, 0x00, 0x00});
  CHECK(raw.receive(12) == Bytes{0x00, 0x03, 0x00, 0x00, 0x00, 0x06, 0x09, 0x03, 0x00, 0x00,
                                 0x00, 0x00});
  const auto stats = server.stats();
  CHECK(stats.forwarded == 3);
  CHECK(stats.rejected == 0);
  // Unit 1 is the gateway's own: 08's restart (0x0001), which it does not serve, is refused
  // there (docs/diagnostics.md).
  raw.send({0x00, 0x04, 0x00, 0x00, 0x00, 0x06, 0x01, 0x08, 0x00, 0x01, 0x00, 0x00});
  CHECK(raw.receive(9) == Bytes{0x00, 0x04, 0x00, 0x00, 0x00, 0x03, 0x01, 0x88, 0x01});
}

TEST_CASE("a request for a passed-through unit with a bad MBAP header closes the connection") {
  RunningServer server;
  RawSocket raw(server.port);
  raw.send({0x00, 0x01, 0x00, 0x01, 0x00, 0x06, 0x09, 0x03, 0x00, 0x00, 0x00, 0x01});
  CHECK(raw.closed_by_server());
  CHECK(server.stats().forwarded == 0);
}
