// build/tiltgate run against simulated Rieker sensors on a pseudo-terminal, read and written
// with the real libmodbus client.
#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <atomic>
#include <bit>
#include <cmath>
#include <netinet/in.h>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using rieker::RiekerSimulator;

namespace {

float float_at(const std::vector<std::uint16_t>& words, std::size_t at) {
  return modbus_get_float_abcd(words.data() + at);
}

std::string string_at(const std::vector<std::uint16_t>& words, std::size_t at, std::size_t chars) {
  std::string text;
  for (std::size_t i = 0; i < chars; ++i) {
    const std::uint16_t w = words[at + i / 2];
    text += char(i % 2 == 0 ? w >> 8 : w & 0xFF);
  }
  return text;
}

// Big-endian words of a float. Not modbus_set_float_abcd: in Debian's libmodbus 3.1.6 it
// copies the bytes in host order, so on x86 it yields BADC (its getter is right, and is used
// here to cross-check).
std::vector<std::uint16_t> abcd_words(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  std::vector<std::uint16_t> words = {std::uint16_t(bits >> 16), std::uint16_t(bits & 0xFFFF)};
  REQUIRE(modbus_get_float_abcd(words.data()) == value);
  return words;
}

}  // namespace

TEST_CASE("a PLC reads every input register and the online bit of each sensor") {
  Plant plant;
  REQUIRE_MESSAGE(plant.wait_online(1), plant.gateway->log());
  REQUIRE(plant.wait_online(3));
  ModbusClient client(plant.port, 1);
  auto words = client.input(0, 25);
  REQUIRE(words.size() == 25);
  CHECK(float_at(words, 0) == 1.5f);
  CHECK(float_at(words, 2) == -2.25f);
  CHECK(std::int16_t(words[4]) == 150);
  CHECK(std::int16_t(words[5]) == -225);
  CHECK((words[6] & 0x0F) == 0x01);  // online, fresh, no failed write, identity known
  CHECK(words[7] < 1000);
  CHECK(words[12] == 65535);        // no NAK
  CHECK(words[13] == 0);            // locked
  CHECK(words[14] == 223);
  CHECK(string_at(words, 16, 10) == "962285    ");
  CHECK(string_at(words, 21, 7) == "Rev A.8");
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{1});

  const auto seq = words[15];
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK(client.input(15, 1).at(0) != seq);  // the data moves

  client.unit(3);
  auto single = client.input(0, 6);
  REQUIRE(single.size() == 6);
  CHECK(float_at(single, 0) == -30.5f);
  CHECK(std::isnan(float_at(single, 2)));
  CHECK(std::int16_t(single[5]) == -32768);  // no Y: the documented "not available"
}

TEST_CASE("holding register writes reach the sensor and read back") {
  Plant plant;
  REQUIRE(plant.wait_online(1));
  ModbusClient client(plant.port, 1);
  // Before any write: unknown (the protocol reads no setting back), the address known.
  const auto before = client.holding(0, 8);
  REQUIRE(before.size() == 8);
  CHECK(before[0] == 0xFFFF);
  CHECK(std::isnan(float_at(before, 1)));
  CHECK(before[5] == 0);  // no command
  CHECK(before[7] == 223);

  CHECK(client.write(0, 2));
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).filter(); }) == 2);
  CHECK(client.holding(0, 1) == std::vector<std::uint16_t>{2});

  CHECK(client.write(1, abcd_words(0.5f)));
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).zero_offset(rieker::Axis::x); }) == 0.5);
  const auto zero = abcd_words(-1.25f);
  CHECK(client.write(3, zero));
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).zero_offset(rieker::Axis::y); }) == -1.25);
  CHECK(client.holding(3, 2) == zero);

  CHECK(client.write(6, 8));  // baud code, pending until restart
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).pending_baud_code(); }) == 8);
  CHECK(client.write(5, 2));  // permanent zero to the current angle
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).zero_offset(rieker::Axis::x); }) == 1.5);

  client.unit(2);
  CHECK(client.write(7, 300));  // re-address boom-right; the gateway follows it
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor_by_address(300) != nullptr; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto status = client.input(6, 9);
  REQUIRE(status.size() == 9);
  CHECK(status[8] == 300);
  CHECK((status[0] & 0x01) == 0x01);

  CHECK(client.write(5, 3));  // restart
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(1).restarts(); }) == 1);
}

TEST_CASE("exceptions: unknown unit, unmapped, split, out of range, a coil not there") {
  Plant plant;
  REQUIRE(plant.wait_online(1));
  ModbusClient client(plant.port, 9);
  CHECK(client.input(0, 2).empty());
  CHECK(client.exception() == 0x0A);
  client.unit(1);
  CHECK(client.input(1, 2).empty());  // splits angle_x and angle_y
  CHECK(client.exception() == 0x02);
  CHECK(client.input(48, 3).empty());  // past the end of the common block
  CHECK(client.exception() == 0x02);
  CHECK(client.coils(1, 1).empty());  // coil 0 is the acknowledgement, nothing after it
  CHECK(client.exception() == 0x02);
  CHECK_FALSE(client.write(0, 7));  // filter 1..6
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(5, 9));  // no such command
  CHECK(client.exception() == 0x03);
  CHECK_FALSE(client.write(1, 0x4000));  // half of zero_x
  CHECK(client.exception() == 0x02);
  CHECK_FALSE(client.write_coil(1, true));
  CHECK(client.exception() == 0x02);
  client.unit(3);
  std::vector<std::uint16_t> zero(2);
  CHECK_FALSE(client.write(3, zero));  // H4360 has no Y zero
  CHECK(client.exception() == 0x02);
}

TEST_CASE("a sensor NAK surfaces as the documented exception") {
  Plant plant;
  REQUIRE(plant.wait_online(1));
  ModbusClient client(plant.port, 1);
  plant.sim->call([](RiekerSimulator& s) { s.sensor(0).faults().busy = 1000; return 0; });
  CHECK_FALSE(client.write(0, 3));
  CHECK(client.exception() == 0x06);
  plant.sim->call([](RiekerSimulator& s) { s.sensor(0).faults().busy = 0; return 0; });
  auto status = client.input(6, 7);
  REQUIRE(status.size() == 7);
  CHECK((status[0] & 0x04) == 0x04);  // last write failed
  CHECK(status[6] == 5);              // last NAK: busy
}

TEST_CASE("writes are refused with 0x01 unless the config turns them on") {
  Plant plant(/*writes=*/false);
  REQUIRE(plant.wait_online(1));
  ModbusClient client(plant.port, 1);
  CHECK_FALSE(client.write(0, 2));
  CHECK(client.exception() == 0x01);
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).filter(); }) == 4);
}

TEST_CASE("an unplugged bus gives 0x0B for measurements, status says why, replug recovers") {
  Plant plant;
  REQUIRE(plant.wait_online(1));
  ModbusClient client(plant.port, 1);
  plant.sim->call([](RiekerSimulator& s) { s.unplug(); return 0; });
  bool unavailable = false;
  for (int i = 0; i < 100 && !unavailable; ++i) {
    unavailable = client.input(0, 2).empty() && client.exception() == 0x0B;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  CHECK(unavailable);
  auto status = client.input(6, 2);
  REQUIRE(status.size() == 2);
  CHECK((status[0] & 0x01) == 0);  // not online
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{0});

  plant.sim->call([](RiekerSimulator& s) { return s.replug().has_value(); });
  CHECK_MESSAGE(plant.wait_online(1, std::chrono::seconds(20)), plant.gateway->log());
  CHECK(plant.gateway->running());
}

TEST_CASE("32 clients at once are served while another is stalled mid-frame") {
  Plant plant;
  REQUIRE(plant.wait_online(1));
  // A client that sends half an MBAP header and stops.
  const int stalled = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(plant.port);
  REQUIRE(::connect(stalled, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  const std::uint8_t half[] = {0x00, 0x01, 0x00};
  REQUIRE(::send(stalled, half, sizeof half, 0) == 3);

  std::atomic<int> answered{0};
  std::vector<std::thread> clients;
  for (int i = 0; i < 32; ++i) {
    clients.emplace_back([&, i] {
      ModbusClient client(plant.port, 1 + i % 3);
      int ok = 0;
      for (int k = 0; k < 5; ++k) ok += client.input(6, 10).size() == 10 ? 1 : 0;
      if (ok == 5) ++answered;
    });
  }
  for (auto& t : clients) t.join();
  CHECK(answered == 32);
  ::close(stalled);
  CHECK(plant.gateway->running());
}

TEST_CASE("the gateway exits cleanly on SIGTERM") {
  Plant plant;
  CHECK(plant.gateway->terminate() == 0);
  CHECK(plant.gateway->log().find("shutting down") != std::string::npos);
}

TEST_CASE("check and map report on a configuration file") {
  TempDir dir;
  const auto bad = dir.write("bad.toml", R"([server]
port = 502

[[bus]]
name = "line1"
port = "/dev/ttyUSB0"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line9"
model = "h6"
address = 223
unit_id = 1
)");
  auto checked = run_tiltgate({"check", "--config", bad.string()});
  CHECK(checked.exit_code == 1);
  CHECK(checked.err.find("bad.toml:11") != std::string::npos);
  CHECK(checked.err.find("line9") != std::string::npos);

  const auto example = std::string(TILTGATE_SOURCE_DIR) + "/examples/tiltgate.toml";
  auto good = run_tiltgate({"check", "--config", example});
  CHECK(good.exit_code == 0);
  auto map = run_tiltgate({"map", "--config", example});
  CHECK(map.exit_code == 0);
  CHECK(map.out.rfind("unit_id,name,table,address,words,type,access,units,description,scale,offset,word_order,port,plc_address,role\n", 0) == 0);
  CHECK(map.out.find("\n1,angle_x,input,0,2,float32,r,deg,") != std::string::npos);
  // The port serving the unit, and the 1-based number a PLC tag import wants.
  CHECK(map.out.find(",ABCD,502,30001,\n") != std::string::npos);
  auto missing = run_tiltgate({"run", "--config", "/nonexistent/tiltgate.toml"});
  CHECK(missing.exit_code == 1);
  auto nonsense = run_tiltgate({"frobnicate"});
  CHECK(nonsense.exit_code != 0);
}
