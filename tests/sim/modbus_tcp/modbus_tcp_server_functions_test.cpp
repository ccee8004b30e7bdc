// The Modbus TCP server's functions over loopback sockets: the real libmodbus client (and raw
// sockets for Read Device Identification) against a fake handler, the handler's exceptions, and
// the server's start and stop. Nothing asserts on speed.
#include <doctest/doctest.h>

#include <modbus.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <string>
#include <vector>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;
namespace asio = boost::asio;

TEST_CASE("a libmodbus client reads and writes every table through the server") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.connected);

  std::uint16_t registers[3] = {};
  REQUIRE(modbus_read_registers(client.ctx, 10, 3, registers) == 3);
  CHECK(registers[0] == 1010);
  CHECK(registers[2] == 1012);
  REQUIRE(modbus_read_input_registers(client.ctx, 7, 2, registers) == 2);
  CHECK(registers[0] == 2007);
  CHECK(registers[1] == 2008);
  std::uint8_t bits[16] = {};
  REQUIRE(modbus_read_bits(client.ctx, 0, 7, bits) == 7);
  CHECK(std::vector<int>(bits, bits + 7) == std::vector<int>{1, 0, 0, 1, 0, 0, 1});
  REQUIRE(modbus_read_input_bits(client.ctx, 1, 4, bits) == 4);
  CHECK(std::vector<int>(bits, bits + 4) == std::vector<int>{0, 1, 0, 1});

  REQUIRE(modbus_write_register(client.ctx, 20, 0xBEEF) == 1);
  CHECK(client.read_holding(20, 0xBEEF));
  const std::uint16_t values[3] = {7, 8, 9};
  REQUIRE(modbus_write_registers(client.ctx, 30, 3, values) == 3);
  REQUIRE(modbus_read_registers(client.ctx, 30, 3, registers) == 3);
  CHECK(std::vector<std::uint16_t>(registers, registers + 3) ==
        std::vector<std::uint16_t>{7, 8, 9});
  REQUIRE(modbus_write_bit(client.ctx, 1, 1) == 1);
  const std::uint8_t coils[9] = {1, 1, 1, 0, 0, 0, 0, 0, 1};
  REQUIRE(modbus_write_bits(client.ctx, 3, 9, coils) == 9);
  REQUIRE(modbus_read_bits(client.ctx, 0, 12, bits) == 12);
  CHECK(std::vector<int>(bits, bits + 12) ==
        std::vector<int>{1, 1, 0, 1, 1, 1, 0, 0, 0, 0, 0, 1});

  const auto stats = server.stats();
  CHECK(stats.requests == 11);
  CHECK(stats.rejected == 0);
}

TEST_CASE("the handler's exceptions reach the libmodbus client as its errno codes") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.connected);
  std::uint16_t value = 0;
  CHECK(modbus_read_registers(client.ctx, 9002, 1, &value) == -1);
  CHECK(errno == EMBXILADD);
  CHECK(modbus_read_input_registers(client.ctx, 9011, 1, &value) == -1);
  CHECK(errno == EMBXGTAR);
  CHECK(modbus_write_register(client.ctx, 9004, 1) == -1);
  CHECK(errno == EMBXSFAIL);
  Client other_unit(server.port, 2);
  REQUIRE(other_unit.connected);
  CHECK(modbus_read_registers(other_unit.ctx, 0, 1, &value) == -1);
  CHECK(errno == EMBXGPATH);
  CHECK(client.read_holding(0, 1000));  // the connection is still good
}

namespace {

Bytes device_id_frame(std::uint16_t transaction, std::uint8_t unit, Bytes pdu) {
  // reserve + push_back: g++ 12 -O2 misreports insert-after-initializer-list as out of bounds.
  Bytes adu;
  adu.reserve(7 + pdu.size());
  for (std::uint8_t b : {std::uint8_t(transaction >> 8), std::uint8_t(transaction), std::uint8_t(0),
                         std::uint8_t(0), std::uint8_t(0), std::uint8_t(pdu.size() + 1), unit}) {
    adu.push_back(b);
  }
  for (std::uint8_t b : pdu) adu.push_back(b);
  return adu;
}

// One whole reply: the MBAP header, then as many bytes as its length field says.
Bytes receive_reply(RawSocket& raw) {
  Bytes reply = raw.receive(7);
  REQUIRE(reply.size() == 7);
  const Bytes rest = raw.receive(std::size_t((reply[4] << 8) | reply[5]) - 1);
  reply.insert(reply.end(), rest.begin(), rest.end());
  return reply;
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

}  // namespace

TEST_CASE("read device identification is answered by the server itself, paged, never by libmodbus") {
  RunningServer server;
  RawSocket raw(server.port);
  // Basic stream: the three basic objects, nothing to follow.
  raw.send(device_id_frame(0x21, 1, {0x2B, 0x0E, 0x01, 0x00}));
  Bytes basic = {0x00, 0x21, 0x00, 0x00, 0x00, 0x1F, 0x01, 0x2B, 0x0E, 0x01, 0x83, 0x00, 0x00,
                 0x03, 0x00, 0x0B};
  for (const Bytes& part : {text("Test Vendor"), Bytes{0x01, 0x03}, text("TV1"), Bytes{0x02, 0x03},
                            text("1.0")}) {
    basic.insert(basic.end(), part.begin(), part.end());
  }
  CHECK(receive_reply(raw) == basic);

  // Extended stream: 0x81 does not fit after 0x80, so it follows on request.
  raw.send(device_id_frame(0x22, 1, {0x2B, 0x0E, 0x03, 0x00}));
  const Bytes first = receive_reply(raw);
  REQUIRE(first.size() == 7 + 7 + 13 + 5 + 5 + 152);
  CHECK(first[11] == 0xFF);  // more follows
  CHECK(first[12] == 0x81);  // next object id
  CHECK(first[13] == 4);     // objects in this reply
  raw.send(device_id_frame(0x23, 1, {0x2B, 0x0E, 0x03, first[12]}));
  const Bytes second = receive_reply(raw);
  REQUIRE(second.size() == 7 + 7 + 152);
  CHECK(Bytes(second.begin() + 7, second.begin() + 16) ==
        Bytes{0x2B, 0x0E, 0x03, 0x83, 0x00, 0x00, 0x01, 0x81, 150});
  CHECK(second.back() == 'b');

  // One object, a missing one (02), an unknown unit (0A), a bad code (03), another MEI (01).
  raw.send(device_id_frame(0x24, 1, {0x2B, 0x0E, 0x04, 0x01}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x24, 0x00, 0x00, 0x00, 0x0D, 0x01, 0x2B, 0x0E, 0x04,
                                    0x83, 0x00, 0x00, 0x01, 0x01, 0x03, 'T', 'V', '1'});
  raw.send(device_id_frame(0x25, 1, {0x2B, 0x0E, 0x04, 0x05}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x25, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x02});
  raw.send(device_id_frame(0x26, 2, {0x2B, 0x0E, 0x01, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x26, 0x00, 0x00, 0x00, 0x03, 0x02, 0xAB, 0x0A});
  raw.send(device_id_frame(0x27, 1, {0x2B, 0x0E, 0x07, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x27, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x03});
  raw.send(device_id_frame(0x28, 1, {0x2B, 0x0D, 0x00, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x28, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x01});
  raw.send(device_id_frame(0x29, 1, {0x2B, 0x0E, 0x01}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x29, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x03});

  const auto stats = server.stats();
  CHECK(stats.requests == 6);
  CHECK(stats.rejected == 3);
  // The connection goes on with ordinary requests.
  raw.send(read_holding_frame(0x2A, 5));
  CHECK(raw.receive(11) == holding_reply(0x2A, 1005));
}

TEST_CASE("stop() closes the acceptor and every connection") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.read_holding(1, 1001));
  server.on_server([&] {
    server.server.stop();
    return 0;
  });
  CHECK(server.eventually([&] { return server.server.client_count() == 0; }));
  std::uint16_t value;
  CHECK(modbus_read_registers(client.ctx, 1, 1, &value) == -1);
  Client late(server.port);
  CHECK_FALSE(late.connected);
}

TEST_CASE("start() reports a port that is already taken") {
  RunningServer first;
  asio::io_context io;
  FakeHandler handler;
  ModbusServerOptions options = test_options();
  options.port = first.port;
  ModbusTcpServer second(io.get_executor(), handler, options);
  auto started = second.start();
  REQUIRE_FALSE(started.has_value());
  CHECK(started.error().find("bind") != std::string::npos);
}
