// Who gets in when the Modbus TCP server is full: idle connections give way to new ones (the
// one idle longest first), never a connection mid-request or waiting for its reply, and one
// address holds at most max_clients_per_host. Clients bound to 127.0.0.2, 127.0.0.3 are other
// hosts to the server (loopback has all of 127.0.0.0/8).
#include <doctest/doctest.h>

#include <modbus.h>

#include <memory>
#include <thread>
#include <vector>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// Opens `n` connections that send nothing, one after the other (each accepted before the next
// connects, so they were idle since in that order).
std::vector<std::unique_ptr<RawSocket>> open_silent(RunningServer& server, int n,
                                                    const char* source = nullptr) {
  std::vector<std::unique_ptr<RawSocket>> sockets;
  for (int i = 0; i < n; ++i) {
    const std::size_t before = server.clients();
    sockets.push_back(std::make_unique<RawSocket>(server.port, source));
    REQUIRE(server.eventually([&] { return server.server.client_count() == before + 1; }));
  }
  return sockets;
}

}  // namespace

TEST_CASE("32 silent connections no longer lock out a client: the one idle longest makes room") {
  ModbusServerOptions options = test_options();
  options.max_clients = 32;
  options.max_clients_per_host = 1024;
  RunningServer server(options);
  auto silent = open_silent(server, 32);
  // A request on an older connection makes it the most recently idle.
  CHECK(answered(*silent[0], 1));

  RawSocket plc(server.port);
  CHECK(answered(plc, 2));
  CHECK(silent[1]->closed_by_server());
  CHECK(server.clients() == 32);
  const auto stats = server.stats();
  CHECK(stats.replaced == 1);
  CHECK(stats.refused == 0);
  CHECK(answered(*silent[0], 3));
  CHECK(answered(*silent[2], 4));
}

TEST_CASE("a connection mid-request or waiting for its handler is never replaced") {
  ModbusServerOptions options = test_options();
  options.max_clients = 3;
  options.max_clients_per_host = 1024;
  RunningServer server(options);
  RawSocket half_sent(server.port);  // oldest
  hold_mid_request(half_sent);
  RawSocket writing(server.port);
  writing.send(write_holding_frame(0x5001, slow_address, 42));
  REQUIRE(server.eventually([&] { return server.handler.slow_write_started.load(); }));
  auto idle = open_silent(server, 1);

  RawSocket second(server.port);
  CHECK(answered(second, 1));
  CHECK(idle[0]->closed_by_server());
  // Now none of the three is idle (second is, but keep it busy too): the next is refused.
  hold_mid_request(second);
  {
    RawSocket refused(server.port);
    CHECK(refused.closed_by_server());
  }
  const auto stats = server.stats();
  CHECK(stats.replaced == 1);
  CHECK(stats.refused == 1);

  // The busy ones were kept: each finishes its request.
  server.on_server([&] {
    server.handler.release();
    return true;
  });
  CHECK(writing.receive(12) == write_holding_frame(0x5001, slow_address, 42));
  const Bytes rest = read_holding_frame(0x4002, 2);
  half_sent.send(Bytes(rest.begin() + 5, rest.end()));
  CHECK(half_sent.receive(11) == holding_reply(0x4002, 1002));
}

TEST_CASE("a ninth connection from one address replaces that address's idle one, not others'") {
  ModbusServerOptions options = test_options();
  options.max_clients_per_host = 8;  // the default
  RunningServer server(options);
  // The other host's connections are idle longer than any of 127.0.0.2's.
  auto others = open_silent(server, 3, "127.0.0.3");
  auto plc_old = open_silent(server, 8, "127.0.0.2");

  RawSocket plc(server.port, "127.0.0.2");  // the PLC back after a cable pull
  CHECK(answered(plc, 1));
  CHECK(plc_old[0]->closed_by_server());
  CHECK(server.stats().replaced == 1);
  CHECK(server.clients() == 3 + 8);
  for (auto& other : others) CHECK(answered(*other, 2));
  CHECK(answered(*plc_old[1], 3));
}

TEST_CASE("an address at max_clients_per_host with none of its connections idle is refused") {
  ModbusServerOptions options = test_options();
  options.max_clients_per_host = 2;
  RunningServer server(options);
  RawSocket first(server.port, "127.0.0.2");
  hold_mid_request(first);
  RawSocket second(server.port, "127.0.0.2");
  hold_mid_request(second);
  {
    RawSocket third(server.port, "127.0.0.2");
    CHECK(third.closed_by_server());
  }
  RawSocket other(server.port, "127.0.0.3");
  CHECK(answered(other, 1));
  const auto stats = server.stats();
  CHECK(stats.refused == 1);
  CHECK(stats.replaced == 0);
}
