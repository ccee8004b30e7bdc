// One PLC function block for every inclinometer: the same libmodbus code reads input
// registers 0..37 of an H6, an H4360 and a Dyna; and the Dyna's EEPROM window through the
// gateway (read-back, reserved writes, a refused value in a location + value request).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "e2e/support/mixed_plant.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// What a PLC function block makes of input registers 0..37, whatever the model.
struct CommonBlock {
  float angle_x = NAN;
  float angle_y = NAN;
  std::int16_t angle_x_cdeg = 0;
  std::int16_t angle_y_cdeg = 0;
  std::uint16_t status = 0;
  std::uint32_t polls_ok = 0;
  std::uint16_t bus_address = 0;
  std::string serial;
  std::string firmware;
  float tilt = NAN;
  std::uint16_t model_code = 0;
};

std::uint32_t uint32_at(const std::vector<std::uint16_t>& words, std::size_t at) {
  return std::uint32_t(words[at]) << 16 | words[at + 1];
}

CommonBlock read_common_block(ModbusClient& client) {
  const auto w = client.input(0, 38);
  REQUIRE(w.size() == 38);
  CommonBlock b;
  b.angle_x = float_at(w, 0);
  b.angle_y = float_at(w, 2);
  b.angle_x_cdeg = std::int16_t(w[4]);
  b.angle_y_cdeg = std::int16_t(w[5]);
  b.status = w[6];
  b.polls_ok = uint32_at(w, 8);
  b.bus_address = w[14];
  b.serial = string_at(w, 16, 10);
  b.firmware = string_at(w, 21, 8);
  b.tilt = float_at(w, 25);
  b.model_code = w[37];
  return b;
}

}  // namespace

TEST_CASE("one client reads input 0..37 from an H6, an H4360 and a Dyna with the same code") {
  MixedPlant plant;
  ModbusClient client(plant.port, kRiekerUnit);
  const CommonBlock h6 = read_common_block(client);
  client.unit(kH4360Unit);
  const CommonBlock h4360 = read_common_block(client);
  client.unit(kModbusDynaUnit);
  const CommonBlock dyna = read_common_block(client);

  CHECK(h6.model_code == 1);
  CHECK(h4360.model_code == 2);
  CHECK(dyna.model_code == 3);
  CHECK(h6.angle_x == 1.5f);
  CHECK(h6.angle_y == -2.25f);
  CHECK(h6.angle_y_cdeg == -225);
  CHECK(h4360.angle_x == -30.5f);
  CHECK(dyna.angle_x == 10.0f);
  for (const CommonBlock* single : {&h4360, &dyna}) {
    CHECK(std::isnan(single->angle_y));
    CHECK(single->angle_y_cdeg == -32768);
    CHECK(single->tilt == std::fabs(single->angle_x));
  }
  CHECK(h6.bus_address == 223);
  CHECK(h4360.bus_address == 224);
  CHECK(dyna.bus_address == 1);
  CHECK(h6.serial == "962285    ");
  CHECK(dyna.serial == "4242      ");
  CHECK(dyna.firmware == "01.07   ");
  for (const CommonBlock* b : {&h6, &h4360, &dyna}) {
    CHECK((b->status & 0x09) == 0x01);  // online, identity known
    CHECK(b->polls_ok > 0);
    // reply_timeout_ms (36) is not asserted: the drivers do not fill it yet (0 until then).
    CHECK(b->firmware.find_first_not_of(' ') != std::string::npos);
  }
}

TEST_CASE("the Dyna's holding registers show its EEPROM, and the window reads the module") {
  MixedPlant plant;
  ModbusClient client(plant.port, kModbusDynaUnit);
  // Read back at identity: baud code 10 (the simulator's), module address 1; no filter.
  const auto common = client.holding(0, 8);
  REQUIRE(common.size() == 8);
  CHECK(common[0] == 0xFFFF);
  CHECK(common[5] == 0);
  CHECK(common[6] == 10);
  CHECK(common[7] == 1);
  CHECK(client.holding(100, 5) == std::vector<std::uint16_t>{0, 0, 0, 0xFFFF, 0xFFFF});

  // Changed behind the gateway's back: selecting the location reads the module.
  plant.modbus_sim->call([](DynaSimulator& s) { return s.sensor(0).set_eeprom(140, 77); });
  CHECK(client.write(103, 140));
  CHECK(client.holding(103, 2) == std::vector<std::uint16_t>{140, 77});

  // Location and value in one request, the value refused for the new location (reserved,
  // without eeprom_reserved_writes): nothing is sent, the selection stays.
  CHECK_FALSE(client.write(103, std::vector<std::uint16_t>{100, 355}));
  CHECK(client.exception() == 0x03);
  CHECK(client.holding(103, 2) == std::vector<std::uint16_t>{140, 77});
  CHECK(eeprom(*plant.modbus_sim, 100) == 0);
  // The old order of checks let a baud code pass that is only good for the old location.
  CHECK(client.write(103, 20));
  CHECK_FALSE(client.write(103, std::vector<std::uint16_t>{22, 355}));
  CHECK(client.exception() == 0x03);
  CHECK(client.holding(103, 1) == std::vector<std::uint16_t>{20});
}

TEST_CASE("with eeprom_reserved_writes the note's example write to location 100 goes through") {
  MixedPlant plant;
  ModbusClient client(plant.port, kNineBitDynaUnit);
  CHECK(client.write(103, std::vector<std::uint16_t>{100, 355}));
  CHECK(eeprom(*plant.nine_bit_sim, 100) == 355);
  CHECK(client.holding(103, 2) == std::vector<std::uint16_t>{100, 355});
  CHECK_FALSE(client.write(103, 101));  // odd: refused all the same
  CHECK(client.exception() == 0x03);
}
