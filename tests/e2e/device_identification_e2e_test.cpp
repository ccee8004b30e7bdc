// Read Device Identification (43 / 14) from build/tiltgate, asked with libmodbus's raw request
// API as a PLC tool would. libmodbus 3.1.6 does not know how long a 43 reply is (its
// modbus_receive_confirmation stops after the MEI type), so the rest of each reply is read
// off the client's socket by the MBAP length.
#include <doctest/doctest.h>

#include <sys/socket.h>
#include <sys/time.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"

using namespace tiltgate::test;

namespace {

using Bytes = std::vector<std::uint8_t>;

// The whole reply ADU to 43 / `mei` / `code` / `object_id` sent to `unit`.
Bytes ask(ModbusClient& client, std::uint8_t unit, std::uint8_t code, std::uint8_t object_id,
          std::uint8_t mei = 0x0E) {
  std::uint8_t request[] = {unit, 0x2B, mei, code, object_id};
  REQUIRE(modbus_send_raw_request(client.raw(), request, sizeof request) == 5 + 6);
  std::uint8_t reply[MODBUS_TCP_MAX_ADU_LENGTH];
  const int got = modbus_receive_confirmation(client.raw(), reply);
  REQUIRE(got >= 9);
  Bytes adu(reply, reply + got);
  const std::size_t total = 6 + std::size_t((adu[4] << 8) | adu[5]);
  REQUIRE(total <= MODBUS_TCP_MAX_ADU_LENGTH);
  const int fd = modbus_get_socket(client.raw());
  timeval timeout{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  while (adu.size() < total) {
    std::uint8_t chunk[MODBUS_TCP_MAX_ADU_LENGTH];
    const ssize_t n = ::recv(fd, chunk, total - adu.size(), 0);
    REQUIRE(n > 0);
    adu.insert(adu.end(), chunk, chunk + n);
  }
  CHECK(adu[6] == unit);
  return adu;
}

struct Identification {
  std::uint8_t conformity = 0;
  std::uint8_t more_follows = 0;
  std::uint8_t next_object = 0;
  std::map<std::uint8_t, std::string> objects;
};

Identification identification(const Bytes& adu) {
  REQUIRE(adu.size() >= 14);
  REQUIRE(adu[7] == 0x2B);
  REQUIRE(adu[8] == 0x0E);
  Identification id{adu[10], adu[11], adu[12], {}};
  std::size_t at = 14;
  for (int i = 0; i < adu[13]; ++i) {
    REQUIRE(at + 2 <= adu.size());
    const std::size_t size = adu[at + 1];
    REQUIRE(at + 2 + size <= adu.size());
    id.objects[adu[at]] = std::string(adu.begin() + at + 2, adu.begin() + at + 2 + size);
    at += 2 + size;
  }
  CHECK(at == adu.size());
  return id;
}

// The exception code of an exception reply to 43, or -1.
int exception_of(const Bytes& adu) { return adu.size() == 9 && adu[7] == 0xAB ? adu[8] : -1; }

}  // namespace

TEST_CASE("a PLC identifies each unit: vendor, model, firmware, serial, bus and gateway") {
  Plant plant;
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  REQUIRE(plant.wait_online(3));
  ModbusClient client(plant.port, 1);

  Identification boom = identification(ask(client, 1, 0x03, 0x00));
  CHECK(boom.conformity == 0x83);
  CHECK(boom.more_follows == 0x00);
  CHECK(boom.objects[0x00] == "Rieker Inc.");
  CHECK(boom.objects[0x01] == "H6");
  CHECK(boom.objects[0x02] == "Rev A.8");
  CHECK(boom.objects[0x04] == "H6 dual-axis inclinometer");
  CHECK(boom.objects[0x05] == "H6");
  CHECK(boom.objects[0x06] == "tiltgate " + boom.objects[0x84]);
  CHECK(boom.objects[0x80] == "962285");
  CHECK(boom.objects[0x81] == "boom-left");
  CHECK(boom.objects[0x82] == "line1");
  CHECK(boom.objects[0x83] == "223");
  CHECK_FALSE(boom.objects[0x84].empty());

  Identification basic = identification(ask(client, 3, 0x01, 0x00));
  CHECK(basic.objects == std::map<std::uint8_t, std::string>{
                             {0x00, "Rieker Inc."}, {0x01, "H4360"}, {0x02, "Rev A.8"}});
  Identification regular = identification(ask(client, 3, 0x02, 0x00));
  CHECK(regular.objects.size() == 6);
  CHECK(regular.objects.count(0x80) == 0);
  Identification mast = identification(ask(client, 3, 0x03, 0x80));
  CHECK(mast.objects[0x80] == "777001");
  CHECK(mast.objects[0x81] == "mast");
  CHECK(mast.objects[0x83] == "101");
  CHECK(mast.objects.count(0x00) == 0);  // the stream started at 0x80

  // Ordinary reads go on over the same connection.
  client.unit(1);
  CHECK(client.input(14, 1) == std::vector<std::uint16_t>{223});
}

TEST_CASE("one object at a time, and the exceptions of function 43") {
  Plant plant;
  REQUIRE(plant.wait_online(2));
  ModbusClient client(plant.port, 2);
  Identification serial = identification(ask(client, 2, 0x04, 0x80));
  CHECK(serial.objects == std::map<std::uint8_t, std::string>{{0x80, "962286"}});
  CHECK(exception_of(ask(client, 2, 0x04, 0x03)) == 0x02);  // no VendorUrl object
  CHECK(exception_of(ask(client, 9, 0x01, 0x00)) == 0x0A);  // no such unit
  CHECK(exception_of(ask(client, 2, 0x05, 0x00)) == 0x03);  // no such read code
  CHECK(exception_of(ask(client, 2, 0x01, 0x00, 0x0D)) == 0x01);  // CANopen MEI type
  // A stream asked to start at an object that does not exist starts over.
  CHECK(identification(ask(client, 2, 0x02, 0x42)).objects.count(0x00) == 1);
  CHECK(client.input(14, 1) == std::vector<std::uint16_t>{224});
  CHECK(plant.gateway->running());
}
