// Mounting corrections, alarms and the offline policy, through build/tiltgate: the bus
// scheduler must run each new reading through the sensor's processing before a read sees it.
#include <doctest/doctest.h>

#include <cmath>
#include <fmt/format.h>
#include <thread>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

// One H6 reading X = 1.5, Y = -2.25, mounted with its axes swapped and X inverted, so the
// gateway must report X = 2.25, Y = 1.5; an X alarm at 2.0 must be up.
struct MountedPlant {
  // offline: extra [[sensor]] keys for the offline policy.
  explicit MountedPlant(const char* offline) {
    rieker::RiekerSimulatorOptions options;
    rieker::SimulatedSensorOptions h6;
    h6.address = 223;
    h6.angle_x = 1.5;
    h6.angle_y = -2.25;
    options.sensors = {h6};
    options.link_path = (dir.path() / "ttyUSB0").string();
    sim = std::make_unique<SimulatorThread>(options);
    const auto config = dir.write(
        "plant.toml",
        server_table(port) +
            bus_table("line1", options.link_path,
                      "timeout_ms = 100\nretries = 0\nreopen_min_ms = 50\nreopen_max_ms = 200") +
            sensor_table("boom", "line1", "h6", 223, 1,
                         fmt::format("poll_ms = 50\nstale_ms = 300\n{}\n"
                                     "mounting = {{ swap_axes = true, invert_x = true }}\n"
                                     "alarms = {{ x_high = 2.0, hysteresis_deg = 0.1 }}",
                                     offline)));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
    ModbusClient client(port, 1);
    for (int i = 0; i < 200 && client.input(0, 2).empty(); ++i) std::this_thread::sleep_for(50ms);
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

float float_at(const std::vector<std::uint16_t>& words, std::size_t at) {
  return modbus_get_float_abcd(words.data() + at);
}

}  // namespace

TEST_CASE("readings are corrected for the mounting and raise alarms before a PLC reads them") {
  MountedPlant plant("");
  ModbusClient client(plant.port, 1);
  auto angles = client.input(0, 6);
  REQUIRE_MESSAGE(angles.size() == 6, plant.gateway->log());
  CHECK(float_at(angles, 0) == 2.25f);
  CHECK(float_at(angles, 2) == 1.5f);
  CHECK(std::int16_t(angles[4]) == 225);
  auto tilt = client.input(25, 3);
  REQUIRE(tilt.size() == 3);
  // tan^2(tilt) = tan^2(2.25) + tan^2(1.5): 2.70331 (sqrt(x^2 + y^2) would be 2.70416).
  CHECK(float_at(tilt, 0) == doctest::Approx(2.7033088).epsilon(1e-6));
  CHECK(tilt[2] == 0x01);  // alarms: X high
  CHECK(client.discrete(0, 3) == std::vector<std::uint8_t>{1, 1, 0});
  CHECK((client.input(6, 1).at(0) & 0x10) == 0x10);  // status bit 4: an alarm is active
}

TEST_CASE("offline = substitute: an unplugged sensor's angles read as the substitute") {
  MountedPlant plant("offline = \"substitute\"\nsubstitute = -999");
  ModbusClient client(plant.port, 1);
  REQUIRE(client.input(0, 2).size() == 2);
  plant.sim->call([](rieker::RiekerSimulator& s) { s.unplug(); return 0; });
  float angle = 0;
  for (int i = 0; i < 100 && angle != -999.0f; ++i) {
    auto words = client.input(0, 2);
    if (words.size() == 2) angle = float_at(words, 0);
    std::this_thread::sleep_for(50ms);
  }
  CHECK(angle == -999.0f);
  CHECK((client.input(6, 1).at(0) & 0x01) == 0);  // and the status says it is offline
}
