// Writes build/tiltgate refuses before anything reaches the bus, seen by the real libmodbus
// client and the simulated Rieker sensors: an address another sensor on the bus has, and a
// float that is not a number (a client that swaps the words of a float32).
#include <doctest/doctest.h>

#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using rieker::RiekerSimulator;

TEST_CASE("re-addressing a sensor to another sensor's address is refused with 0x03, unsent") {
  Plant plant;  // unit 1 at 223, unit 2 at 224, unit 3 at 101, one bus
  REQUIRE_MESSAGE(plant.wait_online(2), plant.gateway->log());
  ModbusClient client(plant.port, 2);
  CHECK_FALSE(client.write(7, 223));
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(7, 101));
  CHECK(client.exception() == 0x03);
  // No Set Address reached the bus: each simulated sensor is where it was, alone.
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).address(); }) == 223);
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(1).address(); }) == 224);
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(2).address(); }) == 101);
  CHECK(plant.gateway->log().find("is taken by sensor") != std::string::npos);
  auto status = client.input(6, 9);
  REQUIRE(status.size() == 9);
  CHECK(status[8] == 224);          // the gateway still reads it at its address
  CHECK((status[0] & 0x04) == 0);   // no write failed on the bus
}

TEST_CASE("a float32 with swapped words (a subnormal) is refused with 0x03 and changes nothing") {
  Plant plant;
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  ModbusClient client(plant.port, 1);
  REQUIRE(client.write(1, std::vector<std::uint16_t>{0x3F00, 0x0000}));  // zero_x = 0.5
  const auto before = client.holding(1, 2);
  REQUIRE(before == std::vector<std::uint16_t>{0x3F00, 0x0000});
  // 0.75 is 3F40 0000; a client that swaps the words (mbpoll -t 4:float without -B) sends
  // 0000 3F40, which is 2.3e-41.
  CHECK_FALSE(client.write(1, std::vector<std::uint16_t>{0x0000, 0x3F40}));
  CHECK(client.exception() == 0x03);
  CHECK(client.holding(1, 2) == before);
  CHECK(plant.sim->call([](RiekerSimulator& s) {
    return s.sensor(0).zero_offset(rieker::Axis::x);
  }) == 0.5);
}
