// Modbus 08 (Diagnostics) and 11 (Get Comm Event Counter) end to end (docs/diagnostics.md):
// build/tiltgate serving simulated Rieker sensors answers a PLC tool's raw requests (libmodbus's
// modbus_send_raw_request) with each unit's counts of its exchanges on the line; the counts move
// with the faults the simulator injects (silence, a broken CRC, NAK 5 busy) on that sensor only,
// and 08 0x000A clears them where writes are allowed, recorded in the audit trail.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"
#include "e2e/support/raw_request.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr std::uint16_t kBusMessages = 0x000B;
constexpr std::uint16_t kCommunicationErrors = 0x000C;
constexpr std::uint16_t kExceptionErrors = 0x000D;
constexpr std::uint16_t kServerMessages = 0x000E;
constexpr std::uint16_t kNoResponse = 0x000F;
constexpr std::uint16_t kNaks = 0x0010;
constexpr std::uint16_t kBusy = 0x0011;
constexpr std::uint16_t kOverruns = 0x0012;

std::uint16_t word_at(const AduBytes& adu, std::size_t at) {
  REQUIRE(adu.size() >= at + 2);
  return std::uint16_t((adu[at] << 8) | adu[at + 1]);
}

// 08 `sub_function` with data 0x0000 to `unit`: the count its reply carries.
std::uint16_t count(ModbusClient& client, std::uint8_t unit, std::uint16_t sub_function) {
  const AduBytes adu = raw_request(client, {unit, 0x08, std::uint8_t(sub_function >> 8),
                                            std::uint8_t(sub_function & 0xFF), 0x00, 0x00});
  REQUIRE(adu.size() == 12);
  REQUIRE(adu[7] == 0x08);
  CHECK(word_at(adu, 8) == sub_function);
  return word_at(adu, 10);
}

// The exception code of a reply, -1 for none.
int exception_in(const AduBytes& adu) {
  return adu.size() == 9 && (adu[7] & 0x80) != 0 ? adu[8] : -1;
}

// Until `done()` or 5 s.
bool wait_for(const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return done();
}

template <class Fault>
void fault_boom(Plant& plant, Fault fault) {
  plant.sim->call([fault](rieker::RiekerSimulator& s) {
    fault(s.sensor(0).faults());  // boom-left, unit 1, address 223
    return 0;
  });
}

}  // namespace

TEST_CASE("08 and 11 from a PLC tool: the echo, each count moving with its fault on its sensor only, and 0x000A clearing them, audited") {
  Plant plant;
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  REQUIRE(plant.wait_online(2));
  ModbusClient client(plant.port, 1);

  // 0x0000 returns the query data.
  const AduBytes echo = raw_request(client, {1, 0x08, 0x00, 0x00, 0x12, 0x34});
  CHECK(echo == AduBytes{echo[0], echo[1], 0, 0, 0, 6, 1, 0x08, 0x00, 0x00, 0x12, 0x34});

  // A healthy line: requests and replies, nothing else.
  CHECK(count(client, 1, kServerMessages) > 0);
  CHECK(count(client, 1, kBusMessages) > count(client, 1, kServerMessages));
  CHECK(count(client, 1, kNoResponse) == 0);
  CHECK(count(client, 1, kCommunicationErrors) == 0);
  CHECK(count(client, 1, kExceptionErrors) == 0);
  CHECK(count(client, 1, kOverruns) == 0);  // a pseudo-terminal counts none
  const AduBytes events = raw_request(client, {1, 0x0B});
  REQUIRE(events.size() == 12);
  CHECK(word_at(events, 8) == 0x0000);
  CHECK(word_at(events, 10) > 0);

  fault_boom(plant, [](rieker::SensorFaults& f) { f.busy = 2; });
  CHECK(wait_for([&] { return count(client, 1, kBusy) >= 2; }));
  CHECK(count(client, 1, kExceptionErrors) >= 2);
  CHECK(count(client, 1, kNaks) == 0);  // busy, every one of them

  fault_boom(plant, [](rieker::SensorFaults& f) { f.silent = 2; });
  CHECK(wait_for([&] { return count(client, 1, kNoResponse) >= 2; }));

  fault_boom(plant, [](rieker::SensorFaults& f) { f.corrupt_crc = 2; });
  CHECK(wait_for([&] { return count(client, 1, kCommunicationErrors) >= 2; }));

  // Its neighbour on the same line saw none of it.
  CHECK(count(client, 2, kNoResponse) == 0);
  CHECK(count(client, 2, kCommunicationErrors) == 0);
  CHECK(count(client, 2, kBusy) == 0);
  CHECK(count(client, 2, kServerMessages) > 0);

  const std::uint16_t before = count(client, 1, kServerMessages);
  const AduBytes cleared = raw_request(client, {1, 0x08, 0x00, 0x0A, 0x00, 0x00});
  CHECK(cleared == AduBytes{cleared[0], cleared[1], 0, 0, 0, 6, 1, 0x08, 0x00, 0x0A, 0x00, 0x00});
  CHECK(count(client, 1, kBusy) == 0);
  CHECK(count(client, 1, kNoResponse) == 0);
  CHECK(count(client, 1, kCommunicationErrors) == 0);
  CHECK(count(client, 1, kServerMessages) < before);
  CHECK(count(client, 2, kServerMessages) > 0);  // another unit's counts are its own
  // "audit: door modbus, who 127.0.0.1:PORT: line1/boom-left counters = reset: ok"
  CHECK_MESSAGE(wait_for([&] {
    const std::string log = plant.gateway->log();
    return log.find("audit: door modbus, who 127.0.0.1:") != std::string::npos &&
           log.find(": line1/boom-left counters = reset: ok") != std::string::npos;
  }), plant.gateway->log());

  // What the gateway does not serve, and malformed requests.
  CHECK(exception_in(raw_request(client, {1, 0x08, 0x00, 0x01, 0x00, 0x00})) == 0x01);  // restart
  CHECK(exception_in(raw_request(client, {1, 0x08, 0x00, 0x0B, 0x00, 0x01})) == 0x03);
  CHECK(exception_in(raw_request(client, {1, 0x08, 0x00, 0x0B})) == 0x03);
  CHECK(exception_in(raw_request(client, {1, 0x0B, 0x00})) == 0x03);
  CHECK(exception_in(raw_request(client, {9, 0x08, 0x00, 0x0E, 0x00, 0x00})) == 0x0A);  // no unit
  // Reads go on over the same connection.
  client.unit(2);
  CHECK_MESSAGE(client.input(0, 2).size() == 2, client.exception());
}

TEST_CASE("clearing the counts is a write: 01 where writes are off, and the counts stay") {
  Plant plant(false);
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  ModbusClient client(plant.port, 1);
  CHECK(wait_for([&] { return count(client, 1, kServerMessages) >= 5; }));
  const std::uint16_t before = count(client, 1, kServerMessages);
  CHECK(exception_in(raw_request(client, {1, 0x08, 0x00, 0x0A, 0x00, 0x00})) == 0x01);
  CHECK(count(client, 1, kServerMessages) >= before);
}

TEST_CASE("an aggregate unit's counts are its sensors' summed, and it clears nothing") {
  Plant plant(true, 40,
              "[[aggregate]]\nunit_id = 200\npoints = [\"angle_x\"]\n"
              "sensors = [\"boom-left\", \"boom-right\"]\n");
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  REQUIRE(plant.wait_online(2));
  ModbusClient client(plant.port, 200);
  fault_boom(plant, [](rieker::SensorFaults& f) { f.silent = 2; });
  ModbusClient units(plant.port, 1);
  REQUIRE(wait_for([&] { return count(units, 1, kNoResponse) >= 2; }));
  CHECK(count(client, 200, kNoResponse) >= 2);
  CHECK(count(client, 200, kServerMessages) >=
        count(units, 2, kServerMessages));  // boom-right's alone are fewer
  CHECK(exception_in(raw_request(client, {200, 0x08, 0x00, 0x0A, 0x00, 0x00})) == 0x01);
  CHECK(count(client, 200, kNoResponse) >= 2);
}
