// A sensor swapped in the field for another one (serial 9600007 where 9600223 was): with
// [[sensor]] serial the device that answers is not served under the old sensor's name (status
// bit 6 and discrete input 7 say "wrong device", its angles read as `offline` says, a write is
// refused with 0x04 and never reaches it, the API and /metrics show it, the log names both
// serials at error), and the right one answering clears all of it. Without the key it is served
// as before, with one warning. The swap goes through a silence, as unplugging a cable does.
#include <doctest/doctest.h>

#include <chrono>
#include <functional>
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
constexpr int kStatusRegister = 6;      // 30007
constexpr int kWrongDeviceInput = 7;    // 10008
constexpr std::uint16_t kWrongDeviceBit = 1 << 6;
const char* const kLabels = "{sensor=\"boom\",bus=\"line1\",unit=\"1\"}";

struct SwapPlant {
  explicit SwapPlant(std::string_view sensor_keys) {
    rieker::RiekerSimulatorOptions options;
    rieker::SimulatedSensorOptions sensor;
    sensor.model = rieker::Model::h6;
    sensor.address = 223;
    sensor.serial = "9600223";
    sensor.angle_x = 1.5;
    options.sensors = {sensor};
    options.link_path = (dir.path() / "ttyUSB0").string();
    sim = std::make_unique<SimulatorThread>(options);
    const auto config = dir.write(
        "plant.toml", server_table(port, "writes = true") + http_table(http_port) +
                          bus_table("line1", options.link_path, "protocol = \"rieker\"") +
                          sensor_table("boom", "line1", "h6", 223, 1,
                                       std::string("poll_ms = 50\n") + std::string(sensor_keys)));
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
  }

  // Until `done` holds, for at most 10 s; whether it did.
  static bool wait_for(const std::function<bool()>& done) {
    const auto limit = std::chrono::steady_clock::now() + 10s;
    while (!done()) {
      if (std::chrono::steady_clock::now() > limit) return false;
      std::this_thread::sleep_for(20ms);
    }
    return true;
  }

  std::size_t log_count(std::string_view text) const {
    const std::string log = gateway->log();
    std::size_t count = 0;
    for (auto at = log.find(text); at != std::string::npos; at = log.find(text, at + 1)) ++count;
    return count;
  }

  // The cable unplugged, another sensor (or the same) plugged in: silent until the gateway has
  // seen it stop answering, then it answers as `serial`.
  void swap_to(const std::string& serial) {
    const std::size_t stopped = log_count("stopped answering");
    sim->call([](RiekerSimulator& s) {
      s.sensor(0).faults().silent = 1'000'000;
      return 0;
    });
    REQUIRE_MESSAGE(wait_for([&] { return log_count("stopped answering") > stopped; }),
                    gateway->log());
    sim->call([&serial](RiekerSimulator& s) {
      s.sensor(0).set_serial(serial);
      s.sensor(0).faults().silent = 0;
      return 0;
    });
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

std::uint16_t status_word(ModbusClient& client) {
  const auto words = client.input(kStatusRegister, 1);
  return words.empty() ? 0 : words[0];
}

bool has(const std::string& text, std::string_view part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("a swapped sensor is not served under the configured sensor's name, and the right one clears it") {
  SwapPlant plant("serial = \"9600223\"");
  ModbusClient client(plant.port, 1);
  REQUIRE_MESSAGE(SwapPlant::wait_for([&] { return !client.input(0, 2).empty(); }),
                  plant.gateway->log());
  CHECK((status_word(client) & kWrongDeviceBit) == 0);
  CHECK(client.discrete(kWrongDeviceInput, 1) == std::vector<std::uint8_t>{0});

  plant.swap_to("9600007");
  REQUIRE_MESSAGE(
      SwapPlant::wait_for([&] { return (status_word(client) & kWrongDeviceBit) != 0; }),
      plant.gateway->log());
  // Its angles read as offline = "exception" (the default) says; the diagnostics stay readable.
  CHECK(client.input(0, 2).empty());
  CHECK(client.error() == kUnavailable);
  CHECK(client.discrete(kWrongDeviceInput, 1) == std::vector<std::uint8_t>{1});
  CHECK(has(plant.gateway->log(),
            "error boom: wrong device at address 223: serial '9600007' answers, the configured "
            "sensor is serial '9600223'"));
  const Response api = get(plant.http_port, "/api/sensors/boom");
  CHECK(has(api.body, "\"serial\":\"9600007\""));
  CHECK(has(api.body, "\"configured_serial\":\"9600223\",\"wrong_device\":true"));
  const Response metrics = get(plant.http_port, "/metrics");
  CHECK(has(metrics.body, std::string("tiltgate_sensor_wrong_device") + kLabels + " 1\n"));
  CHECK(has(metrics.body, std::string("tiltgate_sensor_wrong_device_total") + kLabels + " 1\n"));

  // A zero meant for sensor 9600223 is refused, and never sent to 9600007.
  const std::uint64_t zeros_before = plant.sim->call([](RiekerSimulator& s) {
    return s.sensor(0).requests_of(rieker::Function::set_zero_to_value);
  });
  CHECK_FALSE(client.write(1, std::vector<std::uint16_t>{0x3F80, 0x0000}));  // zero_x = 1.0
  CHECK(client.exception() == 0x04);
  CHECK(plant.sim->call([](RiekerSimulator& s) {
          return s.sensor(0).requests_of(rieker::Function::set_zero_to_value);
        }) == zeros_before);

  plant.swap_to("9600223");
  REQUIRE_MESSAGE(SwapPlant::wait_for([&] { return !client.input(0, 2).empty(); }),
                  plant.gateway->log());
  CHECK((status_word(client) & kWrongDeviceBit) == 0);
  CHECK(client.discrete(kWrongDeviceInput, 1) == std::vector<std::uint8_t>{0});
  CHECK(has(get(plant.http_port, "/api/sensors/boom").body, "\"wrong_device\":false"));
  CHECK(has(get(plant.http_port, "/metrics").body,
            std::string("tiltgate_sensor_wrong_device") + kLabels + " 0\n"));
  CHECK(has(plant.gateway->log(), "boom: serial '9600223' answers at address 223 again: served"));
}

TEST_CASE("without a configured serial a swapped sensor is served as before, with one warning") {
  SwapPlant plant("");
  ModbusClient client(plant.port, 1);
  REQUIRE_MESSAGE(SwapPlant::wait_for([&] { return !client.input(0, 2).empty(); }),
                  plant.gateway->log());

  plant.swap_to("9600007");
  const std::string warning =
      "warning boom: the sensor at address 223 now reports serial '9600007', was '9600223'";
  REQUIRE_MESSAGE(SwapPlant::wait_for([&] { return plant.log_count(warning) > 0; }),
                  plant.gateway->log());
  REQUIRE_MESSAGE(SwapPlant::wait_for([&] { return !client.input(0, 2).empty(); }),
                  plant.gateway->log());
  CHECK((status_word(client) & kWrongDeviceBit) == 0);
  CHECK(has(get(plant.http_port, "/api/sensors/boom").body, "\"wrong_device\":false"));
  CHECK(plant.log_count(warning) == 1);
  CHECK_FALSE(has(plant.gateway->log(), "wrong device"));
}
