// build/tiltgate run with one Modbus RTU bus on the RTU simulator: a cached inclinometer at
// slave 17 (unit 3) and pass_through = [30, 32] with a simulated device at slave 30 only.
// Through the gateway with libmodbus: unit 30 answers as the device does (registers, writes,
// its exceptions), unit 32 (nobody there) fails 0x0B, unit 31 is nobody's (0x0A), and the
// cached sensor keeps polling while a client hammers unit 30.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <fmt/format.h>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/mixed_plant.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr int kCachedUnit = 3;
constexpr int kPassedUnit = 30;
constexpr int kSilentUnit = 32;  // passed through, but no device has that address
constexpr std::size_t kRegisters = 8;

// The RTU bus, and the gateway serving it on a free loopback port.
struct PassThroughPlant {
  explicit PassThroughPlant(bool writes)
      : sim(simulator_options(dir)),
        gateway({"--log-level", "debug", "run", "--config", config(writes).string()},
                dir.path()) {
    REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());
  }

  static modbus_rtu::RtuSimulatorOptions simulator_options(const TempDir& dir) {
    modbus_rtu::RtuSimulatorOptions options;
    options.devices.push_back(modbus_rtu::rtu_inclinometer(17));
    modbus_rtu::SimulatedDevice device(kPassedUnit, kRegisters, kRegisters);
    for (std::size_t i = 0; i < kRegisters; ++i) {
      device.holding()[i] = std::uint16_t(1000 + i);
      device.input()[i] = std::uint16_t(2000 + i);
    }
    options.devices.push_back(std::move(device));
    options.link_path = (dir.path() / "ttyRtu").string();
    return options;
  }

  std::filesystem::path config(bool writes) const {
    return dir.write(
        "pass.toml",
        server_table(port, fmt::format("writes = {}", writes ? "true" : "false")) +
            bus_table("rtu-line", (dir.path() / "ttyRtu").string(),
                      fmt::format("protocol = \"modbus-rtu\"\nbaud = 19200\ntimeout_ms = 100\nretries = 1\n"
                                  "pass_through = [{}, {}]",
                                  kPassedUnit, kSilentUnit)) +
            sensor_table("boom", "rtu-line", "modbus-rtu", 17, kCachedUnit,
                         fmt::format("poll_ms = 50\ndevice = \"{}/examples/devices/rtu-inclinometer.toml\"",
                                     TILTGATE_SOURCE_DIR)));
  }

  std::vector<std::uint16_t> device_holding() {
    return sim.call([](modbus_rtu::RtuSimulator& s) { return s.device(kPassedUnit)->holding(); });
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  RtuSimulatorThread sim;
  GatewayProcess gateway;
};

// The cached sensor's polls_ok (input registers 8-9, uint32 high word first), once online.
std::uint32_t polls_ok(ModbusClient& client) {
  const auto words = client.input(8, 2);
  REQUIRE(words.size() == 2);
  return (std::uint32_t(words[0]) << 16) | words[1];
}

}  // namespace

TEST_CASE("a passed-through unit reads the device's own registers and relays its exceptions") {
  PassThroughPlant plant(false);
  ModbusClient client(plant.port, kPassedUnit);
  const auto holding = client.holding(0, kRegisters);
  INFO(plant.gateway.log());
  REQUIRE(holding.size() == kRegisters);
  CHECK(holding == plant.device_holding());
  const auto input = client.input(2, 3);
  CHECK(input == std::vector<std::uint16_t>{2002, 2003, 2004});
  // Past the device's registers: the device's own 0x02, relayed.
  CHECK(client.holding(6, 4).empty());
  CHECK(client.exception() == 0x02);
}

TEST_CASE("with writes off a write to a passed-through unit is refused 0x01 and never sent") {
  PassThroughPlant plant(false);
  ModbusClient client(plant.port, kPassedUnit);
  CHECK_FALSE(client.write(2, 555));
  CHECK(client.exception() == 0x01);
  CHECK(plant.device_holding()[2] == 1002);
}

TEST_CASE("with writes on a write to a passed-through unit lands in the device") {
  PassThroughPlant plant(true);
  ModbusClient client(plant.port, kPassedUnit);
  INFO(plant.gateway.log());
  CHECK(client.write(2, 555));
  CHECK(client.write(4, {7, 8}));
  const auto holding = plant.device_holding();
  CHECK(holding[2] == 555);
  CHECK(holding[4] == 7);
  CHECK(holding[5] == 8);
}

TEST_CASE("a passed-through unit nobody answers fails 0x0B, a unit nobody serves 0x0A") {
  PassThroughPlant plant(false);
  ModbusClient client(plant.port, kSilentUnit);
  const auto start = std::chrono::steady_clock::now();
  CHECK(client.holding(0, 1).empty());
  CHECK(client.exception() == 0x0B);
  // One attempt of 100 ms and the bus's quiet guard: far below libmodbus's 5 s.
  CHECK(std::chrono::steady_clock::now() - start < 4s);
  client.unit(31);
  CHECK(client.holding(0, 1).empty());
  CHECK(client.exception() == 0x0A);
}

TEST_CASE("the cached sensor keeps polling while a client hammers a passed-through unit") {
  PassThroughPlant plant(false);
  ModbusClient cached(plant.port, kCachedUnit);
  // Online first (status bit 0 of input register 6), so polls_ok counts from here.
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  std::vector<std::uint16_t> status;
  while (std::chrono::steady_clock::now() < deadline) {
    status = cached.input(6, 1);
    if (status.size() == 1 && (status[0] & 0x01) == 0x01) break;
    std::this_thread::sleep_for(50ms);
  }
  REQUIRE_MESSAGE((status.size() == 1 && (status[0] & 0x01) == 0x01), plant.gateway.log());
  const std::uint32_t before = polls_ok(cached);

  std::atomic<bool> stop{false};
  std::atomic<int> answered{0};
  std::thread hammer([&] {
    ModbusClient client(plant.port, kPassedUnit);
    while (!stop) {
      if (client.holding(0, 4).size() == 4) ++answered;
    }
  });
  std::this_thread::sleep_for(1500ms);
  const std::uint32_t during = polls_ok(cached);
  stop = true;
  hammer.join();
  CAPTURE(before);
  CAPTURE(during);
  CAPTURE(answered.load());
  // Both get the bus: polls every 50 ms would be 30; alternating with the hammer, at least a
  // handful even on a slow machine, and the hammer is answered too.
  CHECK(during >= before + 5);
  CHECK(answered >= 5);
}
