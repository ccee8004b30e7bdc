// [server] max_requests_per_s and max_client_requests_per_s on a real server: a request beyond
// the rate waits for its turn and is answered, in order, with its registers; nothing is refused
// or closed. What is checked is what was answered and how many requests waited, never how long:
// the rates' arithmetic has its own unit tests (tests/unit/doors/request_rate_test.cpp).
#include <doctest/doctest.h>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// `count` reads of holding register 10 in one send, as a client that pipelines would send them.
Bytes pipelined_reads(std::uint16_t first_transaction, int count) {
  Bytes all;
  for (int i = 0; i < count; ++i) {
    const Bytes one = read_holding_frame(std::uint16_t(first_transaction + i), 10);
    all.insert(all.end(), one.begin(), one.end());
  }
  return all;
}

// Every one of the `count` replies, in order, with the register's value: no exception.
bool all_answered(RawSocket& socket, std::uint16_t first_transaction, int count) {
  for (int i = 0; i < count; ++i)
    if (socket.receive(11) != holding_reply(std::uint16_t(first_transaction + i), 1010))
      return false;
  return true;
}

}  // namespace

TEST_CASE("a client beyond max_client_requests_per_s waits for its turns and gets every answer") {
  ModbusServerOptions options = test_options();
  // A burst of 4, then one every 200 ms: slow enough that a stalled machine (a sanitizer build
  // beside other builds) does not let a request find its turn come (at 50 a second, 20 ms
  // stalls did).
  options.max_client_requests_per_s = 5;
  RunningServer server(options);
  RawSocket plc(server.port);
  plc.send(pipelined_reads(1, 10));
  CHECK(all_answered(plc, 1, 10));
  const ModbusServerStats stats = server.stats();
  // The burst went at once; the others each waited for their turn (a stalled machine may let
  // one of them find its turn come).
  CHECK(stats.requests_delayed >= 5);
  CHECK(stats.requests_delayed <= 6);
  CHECK(stats.delay_ns > 0);
  CHECK(stats.request_timeouts == 0);
  CHECK(server.clients() == 1);
  // Another client has a rate of its own.
  RawSocket panel(server.port);
  panel.send(pipelined_reads(20, 4));
  CHECK(all_answered(panel, 20, 4));
  CHECK(server.stats().requests_delayed == stats.requests_delayed);
}

TEST_CASE("max_requests_per_s holds every client together, and each is answered in turn") {
  ModbusServerOptions options = test_options();
  options.max_requests_per_s = 5;  // as above: a burst of 4, then one every 200 ms
  RunningServer server(options);
  RawSocket plc(server.port);
  RawSocket historian(server.port);
  plc.send(pipelined_reads(1, 6));
  historian.send(pipelined_reads(100, 6));
  CHECK(all_answered(plc, 1, 6));
  CHECK(all_answered(historian, 100, 6));
  // 12 requests against a burst of 4.
  const ModbusServerStats stats = server.stats();
  CHECK(stats.requests_delayed >= 7);
  CHECK(stats.requests_delayed <= 8);
  CHECK(stats.request_timeouts == 0);
  CHECK(server.clients() == 2);
}

TEST_CASE("without rates no request waits") {
  RunningServer server;  // test_options(): no limits
  RawSocket plc(server.port);
  plc.send(pipelined_reads(1, 40));
  CHECK(all_answered(plc, 1, 40));
  CHECK(server.stats().requests_delayed == 0);
}

TEST_CASE("a reload's new max_requests_per_s applies to the next requests") {
  RunningServer server;
  ModbusServerOptions slower = test_options();
  slower.max_requests_per_s = 50;
  server.on_server([&] {
    server.server.apply(slower);
    return true;
  });
  RawSocket plc(server.port);
  plc.send(pipelined_reads(1, 8));
  CHECK(all_answered(plc, 1, 8));
  CHECK(server.stats().requests_delayed >= 3);
}
