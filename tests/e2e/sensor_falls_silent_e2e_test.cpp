// A sensor that falls silent, with every bus and sensor setting at its default: the online bit
// (status bit 0, discrete input 0, `online` in the status API) clears no later than its angles
// turn 0x0B, although the poll that finds it silent is still running its retries, each waiting
// out the late-reply guard (3 x (50 + 450) ms).
#include <doctest/doctest.h>


#include <chrono>
#include <thread>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using rieker::RiekerSimulator;

namespace {

constexpr int kUnavailable = MODBUS_ENOBASE + 0x0B;

struct DefaultsPlant {
  DefaultsPlant() {
    rieker::RiekerSimulatorOptions options;
    rieker::SimulatedSensorOptions sensor;
    sensor.model = rieker::Model::h6;
    sensor.address = 223;
    options.sensors = {sensor};
    options.link_path = (dir.path() / "ttyUSB0").string();
    sim = std::make_unique<SimulatorThread>(options);
    // Nothing but what a bus and a sensor must say: every timing key at its default.
    const auto config = dir.write("plant.toml", server_table(port) + http_table(http_port) +
                                                    bus_table("line1", options.link_path,
                                                              "protocol = \"rieker\"") +
                                                    sensor_table("boom", "line1", "h6", 223, 1));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

bool api_says_online(std::uint16_t http_port) {
  const Response reply = get(http_port, "/api/sensors/boom");
  REQUIRE(reply.status == 200);
  return reply.body.find("\"online\":true") != std::string::npos;
}

}  // namespace

TEST_CASE("a sensor that falls silent reads offline no later than its angles answer 0x0B") {
  DefaultsPlant plant;
  ModbusClient client(plant.port, 1);
  const auto online_by = std::chrono::steady_clock::now() + 10s;
  while (client.input(0, 2).empty() && std::chrono::steady_clock::now() < online_by)
    std::this_thread::sleep_for(20ms);
  REQUIRE_MESSAGE(!client.input(0, 2).empty(), plant.gateway->log());
  REQUIRE(api_says_online(plant.http_port));

  plant.sim->call([](RiekerSimulator& s) {
    s.sensor(0).faults().silent = 1'000'000;
    return 0;
  });
  const auto silent_since = std::chrono::steady_clock::now();
  bool unavailable = false;
  while (!unavailable && std::chrono::steady_clock::now() - silent_since < 5s) {
    unavailable = client.input(0, 2).empty() && client.error() == kUnavailable;
    if (!unavailable) std::this_thread::sleep_for(10ms);
  }
  REQUIRE(unavailable);
  // Read right after the first 0x0B: the sensor must not still read as online.
  const std::vector<std::uint16_t> status = client.input(6, 1);
  REQUIRE(status.size() == 1);
  CHECK((status[0] & 0x01) == 0);     // bit 0: not online
  CHECK((status[0] & 0x02) == 0x02);  // bit 1: stale
  CHECK(client.discrete(0, 1) == std::vector<std::uint8_t>{0});
  CHECK_FALSE(api_says_online(plant.http_port));
}
