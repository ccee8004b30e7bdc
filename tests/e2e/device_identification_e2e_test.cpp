// Read Device Identification (43 / 14) from build/tiltgate, asked with libmodbus's raw request
// API as a PLC tool would (e2e/support/device_id_client.h).
#include <doctest/doctest.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "e2e/support/device_id_client.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"

using namespace tiltgate::test;

TEST_CASE("a PLC identifies each unit: vendor, model, firmware, serial, bus and gateway") {
  Plant plant;
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  REQUIRE(plant.wait_online(3));
  ModbusClient client(plant.port, 1);

  Identification boom = identification(ask_device_id(client, 1, 0x03, 0x00));
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

  Identification basic = identification(ask_device_id(client, 3, 0x01, 0x00));
  CHECK(basic.objects == std::map<std::uint8_t, std::string>{
                             {0x00, "Rieker Inc."}, {0x01, "H4360"}, {0x02, "Rev A.8"}});
  Identification regular = identification(ask_device_id(client, 3, 0x02, 0x00));
  CHECK(regular.objects.size() == 6);
  CHECK(regular.objects.count(0x80) == 0);
  Identification mast = identification(ask_device_id(client, 3, 0x03, 0x80));
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
  Identification serial = identification(ask_device_id(client, 2, 0x04, 0x80));
  CHECK(serial.objects == std::map<std::uint8_t, std::string>{{0x80, "962286"}});
  CHECK(exception_of(ask_device_id(client, 2, 0x04, 0x03)) == 0x02);  // no VendorUrl object
  CHECK(exception_of(ask_device_id(client, 9, 0x01, 0x00)) == 0x0A);  // no such unit
  CHECK(exception_of(ask_device_id(client, 2, 0x05, 0x00)) == 0x03);  // no such read code
  CHECK(exception_of(ask_device_id(client, 2, 0x01, 0x00, 0x0D)) == 0x01);  // CANopen MEI type
  // A stream asked to start at an object that does not exist starts over.
  CHECK(identification(ask_device_id(client, 2, 0x02, 0x42)).objects.count(0x00) == 1);
  CHECK(client.input(14, 1) == std::vector<std::uint16_t>{224});
  CHECK(plant.gateway->running());
}
