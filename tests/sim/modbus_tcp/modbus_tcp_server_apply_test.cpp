// ModbusTcpServer::apply, what a reload does to the running server: new options at once, the
// listener rebound only for a new address or port (and kept when the new one cannot be had),
// and the clients connected meanwhile left connected.
#include <doctest/doctest.h>

#include <boost/asio/ip/tcp.hpp>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using boost::asio::ip::tcp;

namespace {

// A loopback port nothing listens on right now.
std::uint16_t unused_port() {
  boost::asio::io_context io;
  tcp::acceptor acceptor(io, tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0));
  return acceptor.local_endpoint().port();
}

bool accepts_connections(std::uint16_t port) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  boost::system::error_code ec;
  socket.connect(tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port), ec);
  return !ec;
}

}  // namespace

TEST_CASE("apply: a new port moves the listener and the connected client stays") {
  RunningServer server;
  RawSocket connected(server.port);
  connected.send(read_holding_frame(1, 5));
  REQUIRE(connected.receive(11) == holding_reply(1, 1005));

  const std::uint16_t old_port = server.port;
  const std::uint16_t new_port = unused_port();
  ModbusServerOptions options = test_options();
  options.port = new_port;
  server.on_server([&] {
    server.server.apply(options);
    return 0;
  });
  CHECK(server.on_server([&] { return server.server.local_port(); }) == new_port);
  CHECK_FALSE(accepts_connections(old_port));
  Client fresh(new_port);
  REQUIRE(fresh.connected);
  CHECK(fresh.read_holding(7, 1007));
  // The client of before is still served on its connection.
  connected.send(read_holding_frame(2, 6));
  CHECK(connected.receive(11) == holding_reply(2, 1006));
}

TEST_CASE("apply: an address that cannot be bound keeps the old listener") {
  RunningServer server;
  ModbusServerOptions options = test_options();
  options.listen = "192.0.2.1";  // TEST-NET-1: no interface of this machine has it
  options.port = unused_port();
  server.on_server([&] {
    server.server.apply(options);
    return 0;
  });
  CHECK(server.on_server([&] { return server.server.local_port(); }) == server.port);
  Client client(server.port);
  REQUIRE(client.connected);
  CHECK(client.read_holding(3, 1003));
}

TEST_CASE("apply: other options apply at once, without a rebind") {
  RunningServer server;
  RawSocket first(server.port);
  first.send(read_holding_frame(1, 1));
  REQUIRE(first.receive(11) == holding_reply(1, 1001));
  ModbusServerOptions options = test_options();
  options.max_clients = 1;
  server.on_server([&] {
    server.server.apply(options);
    return 0;
  });
  CHECK(server.on_server([&] { return server.server.local_port(); }) == server.port);
  // max_clients is 1 now: a second client takes the place of the first, idle one.
  RawSocket second(server.port);
  second.send(read_holding_frame(2, 2));
  CHECK(second.receive(11) == holding_reply(2, 1002));
  CHECK(first.closed_by_server());
}

TEST_CASE("apply: the same port on another address moves over, the client stays") {
  RunningServer server;
  RawSocket connected(server.port);
  connected.send(read_holding_frame(1, 5));
  REQUIRE(connected.receive(11) == holding_reply(1, 1005));
  ModbusServerOptions options = test_options();
  options.listen = "0.0.0.0";  // collides with our own 127.0.0.1 listener on that port
  options.port = server.port;
  server.on_server([&] {
    server.server.apply(options);
    return 0;
  });
  CHECK(server.on_server([&] { return server.server.local_port(); }) == server.port);
  Client client(server.port);
  REQUIRE(client.connected);
  CHECK(client.read_holding(3, 1003));
  connected.send(read_holding_frame(2, 6));
  CHECK(connected.receive(11) == holding_reply(2, 1006));
}
