// More than 247 sensors, end to end: build/tiltgate with simulated Rieker buses on ptys and a
// real libmodbus client. An aggregate unit serves several sensors' angles back to back; buses
// with a tcp_port of their own answer the same unit id each with their own sensor; and 480
// sensors on 8 buses load and are served.
#include <doctest/doctest.h>

#include <fmt/format.h>
#include <modbus/modbus.h>

#include <csignal>
#include <chrono>
#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

float aggregate_float(const std::vector<std::uint16_t>& words, std::size_t at) {
  return modbus_get_float_abcd(words.data() + at);
}

rieker::SimulatedSensorOptions h6_at(std::uint16_t address, double x, double y) {
  rieker::SimulatedSensorOptions s;
  s.model = rieker::Model::h6;
  s.address = address;
  s.angle_x = x;
  s.angle_y = y;
  s.serial = fmt::format("9{:05}", address);
  return s;
}

// A simulated Rieker bus with H6 at `sensors`' addresses and angles, on a pty in `dir`.
std::unique_ptr<SimulatorThread> rieker_bus(const TempDir& dir, const std::string& tty,
                                            std::vector<rieker::SimulatedSensorOptions> sensors) {
  rieker::RiekerSimulatorOptions options;
  options.sensors = std::move(sensors);
  options.link_path = (dir.path() / tty).string();
  return std::make_unique<SimulatorThread>(options);
}

// [server] on 127.0.0.1:`port`, no control socket, no HTTP: nothing shared between tests.
std::string server_text(std::uint16_t port) {
  return server_table(port, "control_socket = \"\"") + "\n[http]\nenabled = false\n";
}

std::string bus_text(const std::string& name, const std::string& tty, std::uint16_t tcp_port) {
  std::string extra =
      "protocol = \"rieker\"\nbaud = 125000\ntimeout_ms = 100\nretries = 1\nreopen_min_ms = 50\n"
      "reopen_max_ms = 200\n";
  if (tcp_port != 0) extra += fmt::format("tcp_port = {}\n", tcp_port);
  return bus_table(name, tty, extra);
}

std::string sensor_text(const std::string& name, const std::string& bus, int address,
                        int unit_id, const std::string& more = "") {
  return sensor_table(name, bus, "h6", address, unit_id, "poll_ms = 50\nstale_ms = 1000\n" + more);
}

// Reads until the range answers (the first polls take a moment); empty on time-out.
std::vector<std::uint16_t> read_when_online(ModbusClient& client, int address, int count,
                                            bool input = true) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (std::chrono::steady_clock::now() < deadline) {
    auto words = input ? client.input(address, count) : client.holding(address, count);
    if (!words.empty()) return words;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return {};
}

}  // namespace

TEST_CASE("an aggregate unit serves each simulated sensor's angles and status at its block") {
  TempDir dir;
  const std::uint16_t port = free_tcp_port();
  auto sim = rieker_bus(dir, "ttyUSB0",
                        {h6_at(11, 1.5, -2.25), h6_at(12, 10.0, 20.0), h6_at(13, -30.5, 0.75)});
  std::string config = server_text(port) + bus_text("line1", (dir.path() / "ttyUSB0").string(), 0);
  config += sensor_text("s11", "line1", 11, 1) + sensor_text("s12", "line1", 12, 2) +
            sensor_text("s13", "line1", 13, 3);
  // Listed out of file order: the blocks follow the list.
  config += "[[aggregate]]\nunit_id = 200\npoints = [\"angle_x\", \"angle_y\", \"status\"]\n"
            "sensors = [\"s13\", \"s11\", \"s12\"]\n";
  const auto file = dir.write("plant.toml", config);
  GatewayProcess gateway({"run", "--config", file.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());

  ModbusClient client(port, 200);
  const auto words = read_when_online(client, 0, 15);
  REQUIRE_MESSAGE(words.size() == 15, gateway.log());
  CHECK(aggregate_float(words, 0) == -30.5f);  // s13
  CHECK(aggregate_float(words, 2) == 0.75f);
  CHECK(aggregate_float(words, 5) == 1.5f);    // s11
  CHECK(aggregate_float(words, 7) == -2.25f);
  CHECK(aggregate_float(words, 10) == 10.0f);  // s12
  CHECK(aggregate_float(words, 12) == 20.0f);
  for (std::size_t status : {4u, 9u, 14u}) CHECK((words[status] & 0x01) == 0x01);  // online
  // FC3 reads the same layout; one sensor's block alone; a write is refused.
  const auto holding = read_when_online(client, 5, 5, false);
  REQUIRE(holding.size() == 5);
  CHECK(aggregate_float(holding, 0) == 1.5f);
  CHECK_FALSE(client.write(0, 1));
  CHECK(client.exception() == 0x01);
  // A range splitting a float, or past the last block.
  CHECK(client.input(1, 2).empty());
  CHECK(client.exception() == 0x02);
  CHECK(client.input(14, 2).empty());
  CHECK(client.exception() == 0x02);
  // The sensors' own units are served as before.
  client.unit(2);
  const auto own = client.input(0, 2);
  REQUIRE(own.size() == 2);
  CHECK(aggregate_float(own, 0) == 10.0f);
}

TEST_CASE("two buses on two tcp_ports: the same unit id answers with each bus's own sensor") {
  TempDir dir;
  const std::uint16_t main_port = free_tcp_port();
  std::uint16_t port1 = free_tcp_port();
  std::uint16_t port2 = free_tcp_port();
  while (port1 == main_port) port1 = free_tcp_port();
  while (port2 == main_port || port2 == port1) port2 = free_tcp_port();
  auto sim1 = rieker_bus(dir, "ttyUSB0", {h6_at(21, 4.5, 1.0)});
  auto sim2 = rieker_bus(dir, "ttyUSB1", {h6_at(21, -7.25, 2.0), h6_at(22, 3.0, 3.0)});
  std::string config = server_text(main_port) +
                       bus_text("line1", (dir.path() / "ttyUSB0").string(), port1) +
                       bus_text("line2", (dir.path() / "ttyUSB1").string(), port2);
  config += sensor_text("a", "line1", 21, 1) + sensor_text("b", "line2", 21, 1) +
            sensor_text("c", "line2", 22, 2);
  config += "[[aggregate]]\nunit_id = 100\npoints = [\"angle_x\"]\nbus = \"line2\"\n";
  const auto file = dir.write("plant.toml", config);
  GatewayProcess gateway({"run", "--config", file.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port1), gateway.log());
  REQUIRE_MESSAGE(gateway.wait_listening(port2), gateway.log());

  ModbusClient on_line1(port1, 1);
  ModbusClient on_line2(port2, 1);
  const auto a = read_when_online(on_line1, 0, 2);
  const auto b = read_when_online(on_line2, 0, 2);
  REQUIRE_MESSAGE(a.size() == 2, gateway.log());
  REQUIRE_MESSAGE(b.size() == 2, gateway.log());
  CHECK(aggregate_float(a, 0) == 4.5f);
  CHECK(aggregate_float(b, 0) == -7.25f);
  // Each port serves only its bus's units: unit 2 is line2's, and the aggregate is on line2's.
  on_line1.unit(2);
  CHECK(on_line1.input(0, 2).empty());
  CHECK(on_line1.exception() == 0x0A);
  on_line2.unit(100);
  const auto aggregate = read_when_online(on_line2, 0, 4);
  REQUIRE(aggregate.size() == 4);
  CHECK(aggregate_float(aggregate, 0) == -7.25f);
  CHECK(aggregate_float(aggregate, 2) == 3.0f);
  // Nothing is left on the main port: its unit 1 is nobody's (0x0A, no path).
  ModbusClient on_main(main_port, 1);
  CHECK(on_main.input(0, 2).empty());
  CHECK(on_main.exception() == 0x0A);
}

TEST_CASE("480 sensors on 8 buses with their own ports load, and units on two ports answer") {
  TempDir dir;
  const std::uint16_t main_port = free_tcp_port();
  std::vector<std::uint16_t> ports;
  while (ports.size() < 8) {
    const std::uint16_t port = free_tcp_port();
    if (port != main_port && std::find(ports.begin(), ports.end(), port) == ports.end())
      ports.push_back(port);
  }
  // No tty exists: every sensor stays offline (no serial I/O), and offline measurements read
  // the substitute, its bus number, so each port shows whose sensors it serves.
  std::string config = server_text(main_port);
  for (int bus = 0; bus < 8; ++bus) {
    const std::string name = fmt::format("line{}", bus + 1);
    config += bus_text(name, (dir.path() / fmt::format("nothing{}", bus)).string(), ports[bus]);
    for (int i = 1; i <= 60; ++i)
      config += sensor_text(fmt::format("b{}s{}", bus + 1, i), name, i, i,
                            fmt::format("offline = \"substitute\"\nsubstitute = {}\n", bus + 1));
    config += fmt::format("[[aggregate]]\nunit_id = 200\npoints = [\"angle_x_cdeg\", "
                          "\"angle_y_cdeg\"]\nbus = \"{}\"\n\n",
                          name);
  }
  const auto file = dir.write("plant.toml", config);
  const CommandResult checked = run_tiltgate({"check", "--config", file.string()});
  CHECK_MESSAGE(checked.exit_code == 0, checked.err);
  CHECK(checked.out.find("OK (8 bus(es), 480 sensor(s), 8 aggregate(s))") != std::string::npos);
  const CommandResult map = run_tiltgate({"map", "--config", file.string()});
  CHECK(map.exit_code == 0);
  CHECK(map.out.find(fmt::format("\n60,angle_x,input,0,2,float32,r,deg,X angle after the zero "
                                 "offset and the mounting,1,0,ABCD,{},30001,\n",
                                 ports[7])) != std::string::npos);
  CHECK(map.out.find("\n200,b3s60.angle_y_cdeg,input,119,1,int16,") != std::string::npos);

  GatewayProcess gateway({"run", "--config", file.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(ports[0]), gateway.log());
  REQUIRE_MESSAGE(gateway.wait_listening(ports[7]), gateway.log());
  ModbusClient first(ports[0], 60);
  ModbusClient last(ports[7], 60);
  const auto on_first = first.input(0, 2);
  const auto on_last = last.input(0, 2);
  REQUIRE_MESSAGE(on_first.size() == 2, gateway.log());
  REQUIRE_MESSAGE(on_last.size() == 2, gateway.log());
  CHECK(aggregate_float(on_first, 0) == 1.0f);
  CHECK(aggregate_float(on_last, 0) == 8.0f);
  // All 60 sensors of bus 8 in one request: 120 registers of int16 angles.
  last.unit(200);
  const auto all = last.input(0, 120);
  REQUIRE(all.size() == 120);
  for (std::uint16_t word : all) CHECK(word == 8);  // the substitute, as is
}

namespace {

// Writes `text` over `file`, sends SIGHUP and waits for the reload's summary line.
void reload_with(GatewayProcess& gateway, const TempDir& dir, const std::string& text) {
  const auto reloads = [&] {
    const std::string log = gateway.log();
    std::size_t n = 0;
    for (auto at = log.find("configuration reloaded"); at != std::string::npos;
         at = log.find("configuration reloaded", at + 1))
      ++n;
    return n;
  };
  const std::size_t before = reloads();
  dir.write("plant.toml", text);
  REQUIRE(gateway.signal(SIGHUP));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (reloads() == before && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  REQUIRE_MESSAGE(reloads() > before, gateway.log());
}

}  // namespace

TEST_CASE("SIGHUP: a bus's tcp_port and an aggregate come and go with the file") {
  TempDir dir;
  const std::uint16_t main_port = free_tcp_port();
  std::uint16_t bus_port = free_tcp_port();
  while (bus_port == main_port) bus_port = free_tcp_port();
  auto sim = rieker_bus(dir, "ttyUSB0", {h6_at(31, 2.5, 0.5), h6_at(32, -1.5, 0.25)});
  const std::string tty = (dir.path() / "ttyUSB0").string();
  const std::string sensors = sensor_text("p", "line1", 31, 1) + sensor_text("q", "line1", 32, 2);
  const std::string aggregate =
      "[[aggregate]]\nunit_id = 150\npoints = [\"angle_x\"]\nbus = \"line1\"\n";
  const std::string plain = server_text(main_port) + bus_text("line1", tty, 0) + sensors;
  const auto file = dir.write("plant.toml", plain);
  GatewayProcess gateway({"run", "--config", file.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(main_port), gateway.log());
  ModbusClient on_main(main_port, 150);
  CHECK(on_main.input(0, 2).empty());  // no aggregate yet
  CHECK(on_main.exception() == 0x0A);

  // Added: the aggregate on the main port.
  reload_with(gateway, dir, plain + aggregate);
  const auto added = read_when_online(on_main, 0, 4);
  REQUIRE_MESSAGE(added.size() == 4, gateway.log());
  CHECK(aggregate_float(added, 0) == 2.5f);
  CHECK(aggregate_float(added, 2) == -1.5f);

  // Moved with its bus to the bus's own port; the main port no longer has it.
  reload_with(gateway, dir,
              server_text(main_port) + bus_text("line1", tty, bus_port) + sensors + aggregate);
  REQUIRE_MESSAGE(gateway.wait_listening(bus_port), gateway.log());
  ModbusClient on_bus(bus_port, 150);
  const auto moved = read_when_online(on_bus, 0, 4);
  REQUIRE_MESSAGE(moved.size() == 4, gateway.log());
  CHECK(aggregate_float(moved, 2) == -1.5f);
  CHECK(on_main.input(0, 4).empty());
  CHECK(on_main.exception() == 0x0A);
  // The tty stayed open: a port is routing, not a line setting.
  CHECK(gateway.log().find("buses kept: line1; reopened: -") != std::string::npos);

  // Changed (one point fewer per block is the same here; a sensor list instead of the bus),
  // then removed with the bus's port.
  reload_with(gateway, dir,
              server_text(main_port) + bus_text("line1", tty, bus_port) + sensors +
                  "[[aggregate]]\nunit_id = 150\npoints = [\"status\"]\nsensors = [\"q\"]\n");
  const auto changed = read_when_online(on_bus, 0, 1);
  REQUIRE(changed.size() == 1);
  CHECK((changed[0] & 0x01) == 0x01);
  CHECK(on_bus.input(0, 2).empty());  // one sensor, one register now
  reload_with(gateway, dir, plain);
  CHECK(gateway.log().find(fmt::format("Modbus TCP port {} closed", bus_port)) !=
        std::string::npos);
  ModbusClient unit_on_main(main_port, 1);
  CHECK(read_when_online(unit_on_main, 0, 2).size() == 2);
}
