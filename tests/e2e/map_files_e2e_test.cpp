// build/tiltgate serving a map file, read with libmodbus' own decoders: a float in all four
// word/byte orders, a float64, scaled integers, bits, and a write through a scaled point.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <bit>
#include <cstring>
#include <thread>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using rieker::RiekerSimulator;

namespace {

// angle_x of the simulated H6 is 1.5 degrees, angle_y -2.25.
constexpr std::string_view kMap = R"(
[[point]]
name = "x_abcd"
table = "input"
address = 0
type = "float32"
word_order = "ABCD"
source = "angle_x"

[[point]]
name = "x_cdab"
table = "input"
address = 2
type = "float32"
word_order = "CDAB"
source = "angle_x"

[[point]]
name = "x_badc"
table = "input"
address = 4
type = "float32"
word_order = "BADC"
source = "angle_x"

[[point]]
name = "x_dcba"
table = "input"
address = 6
type = "float32"
word_order = "DCBA"
source = "angle_x"

[[point]]
name = "y_f64"
table = "input"
address = 8
type = "float64"
word_order = "DCBA"
source = "angle_y"

[[point]]
name = "y_cdeg"
table = "input"
address = 12
type = "int16"
scale = 100
source = "angle_y"

[[point]]
name = "y_milli"
table = "input"
address = 13
type = "int32"
word_order = "CDAB"
scale = 1000
source = "angle_y"

[[point]]
name = "online"
table = "discrete"
address = 0
type = "bool"
source = "online"

[[point]]
name = "online_coil"
table = "coil"
address = 0
type = "bool"
source = "status"
bit = 0

[[point]]
name = "zero_x"
table = "holding"
address = 0
type = "int16"
scale = 100
write = "zero_x"
min = -180
max = 180
)";

struct MapPlant {
  MapPlant() {
    rieker::RiekerSimulatorOptions options;
    rieker::SimulatedSensorOptions h6;
    h6.model = rieker::Model::h6;
    h6.address = 223;
    h6.angle_x = 1.5;
    h6.angle_y = -2.25;
    h6.serial = "962285";
    options.sensors = {h6};
    options.link_path = (dir.path() / "ttyUSB0").string();
    sim = std::make_unique<SimulatorThread>(options);
    dir.write("orders.toml", std::string(kMap));
    const auto config = dir.write(
        "plant.toml",
        server_table(port, "writes = true") +
            bus_table("line1", options.link_path,
                      "timeout_ms = 100\nreopen_min_ms = 50\nreopen_max_ms = 200") +
            sensor_table("boom", "line1", "h6", 223, 1, "poll_ms = 50\nmap = \"orders.toml\""));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
  }

  bool wait_online() {
    ModbusClient client(port, 1);
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
      if (!client.input(0, 2).empty()) return true;
      std::this_thread::sleep_for(50ms);
    }
    return false;
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

// A float64 from four registers in DCBA order (HGFEDCBA): every byte reversed.
double float64_dcba(const std::uint16_t* words) {
  std::uint64_t bits = 0;
  for (int i = 3; i >= 0; --i) {
    const std::uint16_t swapped = std::uint16_t((words[i] << 8) | (words[i] >> 8));
    bits = (bits << 16) | swapped;
  }
  return std::bit_cast<double>(bits);
}

}  // namespace

TEST_CASE("map file: libmodbus decodes a float in each of the four orders") {
  MapPlant plant;
  REQUIRE_MESSAGE(plant.wait_online(), plant.gateway->log());
  ModbusClient client(plant.port, 1);
  const auto words = client.input(0, 15);
  REQUIRE(words.size() == 15);
  CHECK(modbus_get_float_abcd(&words[0]) == 1.5f);
  CHECK(modbus_get_float_cdab(&words[2]) == 1.5f);
  CHECK(modbus_get_float_badc(&words[4]) == 1.5f);
  CHECK(modbus_get_float_dcba(&words[6]) == 1.5f);
  CHECK(float64_dcba(&words[8]) == -2.25);
  CHECK(std::int16_t(words[12]) == -225);
  const auto milli = std::int32_t(std::uint32_t(words[14]) << 16 | words[13]);  // low word first
  CHECK(milli == -2250);
}

TEST_CASE("map file: bits in discrete inputs and coils, and a write through a scaled point") {
  MapPlant plant;
  REQUIRE_MESSAGE(plant.wait_online(), plant.gateway->log());
  ModbusClient client(plant.port, 1);
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{1});
  CHECK(client.coils(0, 1) == std::vector<std::uint8_t>{1});
  CHECK(client.write(0, std::uint16_t(std::int16_t(-150))));  // -1.5 degrees
  CHECK(plant.sim->call(
            [](RiekerSimulator& s) { return s.sensor(0).zero_offset(rieker::Axis::x); }) == -1.5);
  CHECK(client.holding(0, 1) == std::vector<std::uint16_t>{std::uint16_t(std::int16_t(-150))});
  CHECK_FALSE(client.write(0, std::uint16_t(20000)));  // 200 degrees
  CHECK(client.exception() == 0x03);
  CHECK(client.input(16, 1).empty());  // past the map
  CHECK(client.exception() == 0x02);
}

TEST_CASE("map file: check reports a map file's mistake at its line and refuses to run") {
  TempDir dir;
  dir.write("bad-map.toml",
            "[[point]]\nname = \"a\"\ntable = \"input\"\naddress = 0\n"
            "type = \"int16\"\nsource = \"angle_x\"\nscale = 1000\n");
  const auto config = dir.write("plant.toml",
                                "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n[[sensor]]\n"
                                "name = \"boom\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 223\n"
                                "unit_id = 1\nmap = \"bad-map.toml\"\n");
  auto checked = run_tiltgate({"check", "--config", config.string()});
  CHECK(checked.exit_code == 1);
  CHECK(checked.err.find("bad-map.toml:7:1: point[0].scale: int16 cannot hold angle_x") !=
        std::string::npos);
  auto run = run_tiltgate({"run", "--config", config.string()});
  CHECK(run.exit_code == 1);
}

TEST_CASE("map file: check reports key errors and map problems together, in one run") {
  TempDir dir;
  // Point "b" overlaps "a"; "c" has a misspelt key.
  dir.write("bad-map.toml",
            "[[point]]\nname = \"a\"\ntable = \"input\"\naddress = 0\ntype = \"float32\"\n"
            "source = \"angle_x\"\n[[point]]\nname = \"b\"\ntable = \"input\"\naddress = 1\n"
            "type = \"uint16\"\nsource = \"status\"\n[[point]]\nname = \"c\"\n"
            "table = \"input\"\naddress = 5\ntype = \"uint16\"\nsource = \"status\"\nscael = 10\n");
  const auto config = dir.write("plant.toml",
                                "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\nbaudrate = 9600\n"
                                "[[sensor]]\nname = \"boom\"\nbus = \"line1\"\nmodel = \"h6\"\n"
                                "address = 223\nunit_id = 1\nmap = \"bad-map.toml\"\n");
  const std::string map = (dir.path() / "bad-map.toml").string();
  auto checked = run_tiltgate({"check", "--config", config.string()});
  CHECK(checked.exit_code == 1);
  INFO(checked.err);
  CHECK(checked.err.find(config.string() + ":4:1: bus[0].baudrate: unknown key") !=
        std::string::npos);
  CHECK(checked.err.find(map + ":10:1: point[1].address: \"b\" at input 1..1 overlaps") !=
        std::string::npos);
  CHECK(checked.err.find(map + ":19:1: point[2].scael: unknown key") != std::string::npos);
  CHECK(checked.err.find("3 error(s)") != std::string::npos);
}

TEST_CASE("bounded input: check and run refuse /dev/zero and a FIFO as config or map at once") {
  TempDir dir;
  auto zero = run_tiltgate({"check", "--config", "/dev/zero"});
  CHECK(zero.exit_code == 1);
  CHECK(zero.err.find("/dev/zero: is a character device, expected a regular file") !=
        std::string::npos);
  const std::string fifo = (dir.path() / "plant.fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  auto waited = run_tiltgate({"run", "--config", fifo});
  CHECK(waited.exit_code == 1);
  CHECK(waited.err.find("is a FIFO, expected a regular file") != std::string::npos);
  const auto config = dir.write("plant.toml",
                                "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n[[sensor]]\n"
                                "name = \"boom\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 223\n"
                                "unit_id = 1\nmap = \"/dev/zero\"\n");
  auto map = run_tiltgate({"check", "--config", config.string()});
  CHECK(map.exit_code == 1);
  INFO(map.err);
  CHECK(map.err.find("is a character device, expected a regular file") != std::string::npos);
}
