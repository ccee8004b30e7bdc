// Who sent a write (ModbusRequest::origin, for the audit trail): the connection fills it in for
// writes, door "modbus" and the client's address and port; a read carries none.
#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <string>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// "127.0.0.1:50122": the socket's own end, as the server sees its peer.
std::string local_end(const RawSocket& socket) {
  sockaddr_in local{};
  socklen_t size = sizeof local;
  REQUIRE(::getsockname(socket.fd, reinterpret_cast<sockaddr*>(&local), &size) == 0);
  char text[INET_ADDRSTRLEN];
  ::inet_ntop(AF_INET, &local.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(local.sin_port));
}

}  // namespace

TEST_CASE("a write carries who sent it (door modbus, the client address and port), a read none") {
  RunningServer server;
  RawSocket plc(server.port, "127.0.0.1");
  plc.send(write_holding_frame(1, 20, 42));
  CHECK(plc.receive(12) == write_holding_frame(1, 20, 42));  // 06 echoes the request
  CHECK(answered(plc, 2));
  plc.send(write_holding_frame(3, 21, 43));
  CHECK(plc.receive(12) == write_holding_frame(3, 21, 43));
  const auto origins = server.on_server([&] { return server.handler.origins; });
  const WriteOrigin write{"modbus", local_end(plc)};
  REQUIRE(origins.size() == 3);
  CHECK(origins[0] == write);
  CHECK(origins[1] == WriteOrigin{});  // the read between the writes
  CHECK(origins[2] == write);
}
