// The Modbus TCP server against clients that misbehave, over loopback sockets: malformed,
// pipelined and split requests, stalled, garbage-sending, silent and slow clients, and
// max_clients. The server runs on a background thread; clients run on the test thread (or
// helper threads) with generous time-outs, and nothing asserts on speed.
#include <doctest/doctest.h>

#include <modbus.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("malformed requests get the parser's exception and never reach libmodbus") {
  RunningServer server;
  RawSocket raw(server.port);
  // CVE-2022-0367: write-and-read with byte counts that overflow the frame.
  raw.send({0x00, 0x07, 0x00, 0x00, 0x00, 0x0C, 0x01, 0x17, 0x00, 0x00, 0x00, 0x7D, 0x00, 0x00,
            0x00, 0x79, 0xF2, 0x00});
  CHECK(raw.receive(9) == Bytes{0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x01, 0x97, 0x01});
  // A short 07 (read exception status) and a short 12 (comm event log).
  raw.send({0x00, 0x08, 0x00, 0x00, 0x00, 0x02, 0x01, 0x07});
  CHECK(raw.receive(9) == Bytes{0x00, 0x08, 0x00, 0x00, 0x00, 0x03, 0x01, 0x87, 0x01});
  raw.send({0x00, 0x09, 0x00, 0x00, 0x00, 0x02, 0x01, 0x0C});
  CHECK(raw.receive(9) == Bytes{0x00, 0x09, 0x00, 0x00, 0x00, 0x03, 0x01, 0x8C, 0x01});
  // Read 0 registers; write 2 registers with a byte count of 3.
  raw.send({0x00, 0x0A, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x00, 0x00, 0x00});
  CHECK(raw.receive(9) == Bytes{0x00, 0x0A, 0x00, 0x00, 0x00, 0x03, 0x01, 0x83, 0x03});
  raw.send({0x00, 0x0B, 0x00, 0x00, 0x00, 0x0A, 0x01, 0x10, 0x00, 0x00, 0x00, 0x02, 0x03, 0x00,
            0x01, 0x02});
  CHECK(raw.receive(9) == Bytes{0x00, 0x0B, 0x00, 0x00, 0x00, 0x03, 0x01, 0x90, 0x03});
  const auto stats = server.stats();
  CHECK(stats.rejected == 5);
  CHECK(stats.requests == 0);
  // Still served afterwards.
  raw.send(read_holding_frame(0x0C, 5));
  CHECK(raw.receive(11) == holding_reply(0x0C, 1005));
}

TEST_CASE("pipelined and split requests are answered in order") {
  RunningServer server;
  RawSocket raw(server.port);
  Bytes two = read_holding_frame(1, 1);
  const Bytes second = read_holding_frame(2, 2);
  two.insert(two.end(), second.begin(), second.end());
  raw.send(two);
  CHECK(raw.receive(11) == holding_reply(1, 1001));
  CHECK(raw.receive(11) == holding_reply(2, 1002));
  const Bytes third = read_holding_frame(3, 3);
  raw.send(Bytes(third.begin(), third.begin() + 4));
  std::this_thread::sleep_for(20ms);
  raw.send(Bytes(third.begin() + 4, third.end()));
  CHECK(raw.receive(11) == holding_reply(3, 1003));
}

TEST_CASE("32 clients are served while another stalls half-way through a frame") {
  RunningServer server;
  RawSocket stalled(server.port);
  stalled.send({0x00, 0x01, 0x00});  // half an MBAP header, then nothing
  std::atomic<int> succeeded{0};
  {
    std::vector<std::jthread> clients;
    for (int c = 0; c < 32; ++c) {
      clients.emplace_back([&server, &succeeded, c] {
        Client client(server.port);
        bool ok = client.connected;
        for (int i = 0; i < 20 && ok; ++i) ok = client.read_holding(c + i, 1000 + c + i);
        if (ok) ++succeeded;
      });
    }
  }
  CHECK(succeeded == 32);
  CHECK(server.stats().accepted == 33);
}

TEST_CASE("one client over max_clients, none idle, is accepted and closed, the others unaffected") {
  ModbusServerOptions options = test_options();
  options.max_clients = 2;
  RunningServer server(options);
  // Idle connections would give way (modbus_tcp_server_admission_test.cpp): these are mid-request.
  auto first = std::make_unique<RawSocket>(server.port);
  hold_mid_request(*first);
  RawSocket second(server.port);
  hold_mid_request(second);
  {
    Client third(server.port);
    std::uint16_t value;
    CHECK(modbus_read_registers(third.ctx, 3, 1, &value) == -1);
  }
  CHECK(server.stats().refused == 1);
  CHECK(server.stats().replaced == 0);
  const Bytes rest = read_holding_frame(0x4002, 2);
  second.send(Bytes(rest.begin() + 5, rest.end()));
  CHECK(second.receive(11) == holding_reply(0x4002, 1002));
  // A freed place is taken again.
  first.reset();
  CHECK(server.eventually([&] { return server.server.client_count() == 1; }));
  Client fourth(server.port);
  CHECK(fourth.read_holding(4, 1004));
}

TEST_CASE("a client sending garbage is closed and the others are still served") {
  RunningServer server;
  Client good(server.port);
  REQUIRE(good.read_holding(1, 1001));
  RawSocket garbage(server.port);
  garbage.send({'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P', '/', '1', '.', '1', '\r', '\n'});
  CHECK(garbage.closed_by_server());
  RawSocket bad_length(server.port);
  bad_length.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x01});  // MBAP length 1
  CHECK(bad_length.closed_by_server());
  CHECK(good.read_holding(2, 1002));
  const auto stats = server.stats();
  CHECK(stats.framing_errors == 2);
}

TEST_CASE("a request and garbage behind it in one send: the request is answered, then closed") {
  RunningServer server;
  RawSocket raw(server.port);
  Bytes stream = read_holding_frame(7, 7);
  const Bytes garbage{'G', 'E', 'T', ' ', '/', ' ', 'H'};
  stream.insert(stream.end(), garbage.begin(), garbage.end());
  raw.send(stream);
  CHECK(raw.receive(11) == holding_reply(7, 1007));
  CHECK(raw.closed_by_server());
  CHECK(server.stats().framing_errors == 1);
}

TEST_CASE("a half-sent request is dropped after request_timeout, a silent client after idle") {
  ModbusServerOptions options = test_options();
  options.request_timeout = 200ms;
  options.idle_timeout = 300ms;
  RunningServer server(options);
  RawSocket half(server.port);
  half.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03});
  RawSocket silent(server.port);
  CHECK(half.closed_by_server());
  CHECK(silent.closed_by_server());
  const auto stats = server.stats();
  CHECK(stats.request_timeouts == 1);
  CHECK(stats.idle_timeouts == 1);
  CHECK(server.eventually([&] { return server.server.client_count() == 0; }));
}

TEST_CASE("after many served requests a half-sent request and then silence still time out") {
  // The watchdog is not woken for each request's deadline change; the deadlines it enforces
  // must still be the latest ones.
  ModbusServerOptions options = test_options();
  options.request_timeout = 200ms;
  options.idle_timeout = 300ms;
  RunningServer server(options);
  RawSocket half(server.port);
  RawSocket silent(server.port);
  for (std::uint16_t i = 0; i < 50; ++i) {
    half.send(read_holding_frame(i, 5));
    REQUIRE(half.receive(11) == holding_reply(i, 1005));
    silent.send(read_holding_frame(i, 5));
    REQUIRE(silent.receive(11) == holding_reply(i, 1005));
  }
  half.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03});
  CHECK(half.closed_by_server());
  CHECK(silent.closed_by_server());
  const auto stats = server.stats();
  CHECK(stats.requests == 100);
  CHECK(stats.request_timeouts == 1);
  CHECK(stats.idle_timeouts == 1);
}

TEST_CASE("a slow write on one connection does not hold up reads on another") {
  RunningServer server;
  std::atomic<bool> write_done{false};
  std::atomic<int> write_result{0};
  std::jthread writer([&] {
    Client client(server.port);
    modbus_set_response_timeout(client.ctx, 20, 0);  // released by the test below
    write_result = modbus_write_register(client.ctx, slow_address, 42);
    write_done = true;
  });
  const bool started = server.eventually([&] { return server.handler.slow_write_started.load(); });
  CHECK(started);
  Client reader(server.port);
  for (int i = 0; i < 20; ++i) CHECK(reader.read_holding(i, 1000 + i));
  // Every read above was answered while the write was still waiting in the handler.
  CHECK_FALSE(write_done);
  server.on_server([&] {
    server.handler.release();
    return 0;
  });
  writer.join();
  CHECK(write_result == 1);
  CHECK(reader.read_holding(slow_address, 42));
}

TEST_CASE("a request the handler never answers is answered 0x0B at handler_timeout, its late reply dropped") {
  ModbusServerOptions options = test_options();
  options.handler_timeout = std::chrono::milliseconds(300);
  RunningServer server(options);
  RawSocket socket(server.port);
  socket.send(write_holding_frame(0x0101, slow_address, 42));
  // Function 06 with the exception bit, code 0B: the connection answered for the handler.
  const Bytes expected = {0x01, 0x01, 0x00, 0x00, 0x00, 0x03, 0x01, 0x86, 0x0B};
  CHECK(socket.receive(expected.size()) == expected);
  // The connection serves on, and the handler's reply, when it comes, is not sent.
  CHECK(answered(socket, 0x0202));
  server.on_server([&] {
    server.handler.release();
    return 0;
  });
  CHECK(answered(socket, 0x0303));
  CHECK(server.clients() == 1);
}

TEST_CASE("a stopped server is finished only once its last connection and handler are done") {
  RunningServer server;
  RawSocket socket(server.port);
  socket.send(write_holding_frame(0x0404, slow_address, 7));
  CHECK(server.eventually([&] { return server.handler.slow_write_started.load(); }));
  server.on_server([&] {
    server.server.stop();
    return 0;
  });
  // The connection is closed, but the write it handed over still runs in the handler.
  CHECK(server.eventually([&] { return server.server.client_count() == 0; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the accept loop has ended
  CHECK_FALSE(server.on_server([&] { return server.server.finished(); }));
  server.on_server([&] {
    server.handler.release();
    return 0;
  });
  CHECK(server.eventually([&] { return server.server.finished(); }));
}
