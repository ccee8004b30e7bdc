// build/tiltgate with a Modbus RTU inclinometer whose device profile names its identity
// ([identity] in examples/devices/rtu-inclinometer.toml): the serial, firmware and model reach
// the status API, Read Device Identification (FC 43 / 14, asked with libmodbus) and the common
// block's serial and firmware registers; and a device that answers again after being offline
// has its identity read again (it may be another one).
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/device_id_client.h"
#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/mixed_plant.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr int kUnit = 4;
constexpr std::uint8_t kSlave = 9;

const std::string kProfile =
    std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";

// Polls /api/sensors/mast until `part` is in it; its last body either way.
std::string wait_api(std::uint16_t http_port, const std::string& part) {
  std::string body;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    body = get(http_port, "/api/sensors/mast").body;
    if (body.find(part) != std::string::npos) break;
    std::this_thread::sleep_for(50ms);
  }
  return body;
}

struct RtuPlant {
  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::uint16_t http_port = free_tcp_port();
  RtuSimulatorThread sim;
  GatewayProcess gateway;

  static modbus_rtu::RtuSimulatorOptions options(const TempDir& dir) {
    modbus_rtu::RtuSimulatorOptions o;
    o.devices.push_back(modbus_rtu::rtu_inclinometer(kSlave));
    o.link_path = (dir.path() / "ttyRtu").string();
    return o;
  }

  RtuPlant()
      : sim(options(dir)),
        gateway({"run", "--config",
                 dir.write("rtu.toml",
                           server_table(port) + http_table(http_port) +
                               bus_table("rtu-line", (dir.path() / "ttyRtu").string(),
                                         "protocol = \"modbus-rtu\"\ntimeout_ms = 100\nretries = 0") +
                               sensor_table("mast", "rtu-line", "modbus-rtu", kSlave, kUnit,
                                            "poll_ms = 50\ndevice = \"" + kProfile + "\""))
                     .string()},
                dir.path()) {}
};

}  // namespace

TEST_CASE("a Modbus RTU profile's identity reaches the API, FC 43 and the common block") {
  RtuPlant plant;
  REQUIRE_MESSAGE(plant.gateway.wait_listening(plant.port), plant.gateway.log());
  const std::string api = wait_api(plant.http_port, "\"serial\":\"20240917\"");
  INFO(api);
  // The model is the profile's model_name (the device's own model number is 360).
  CHECK(api.find("\"model\":\"RTU inclinometer\",\"serial\":\"20240917\",\"firmware\":\"1.02\"") !=
        std::string::npos);

  ModbusClient client(plant.port, kUnit);
  // The API shows the driver's identity as soon as it is read, at the start of the first poll;
  // FC 43 and the common block show the snapshot published when that poll has ended (slow
  // under the sanitizers), so the test waits for the serial there.
  Identification id = identification(ask_device_id(client, kUnit, 0x03, 0x00));
  for (int tries = 0; tries < 100 && id.objects[0x80] != "20240917"; ++tries) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    id = identification(ask_device_id(client, kUnit, 0x03, 0x00));
  }
  CHECK(id.objects.at(0x02) == "1.02");      // major/minor revision
  CHECK(id.objects.at(0x05) == "RTU inclinometer");  // model name
  CHECK(id.objects.at(0x80) == "20240917");  // serial number
  CHECK(id.objects.at(0x01) == "Modbus RTU device");  // product code: the family's

  const std::vector<std::uint16_t> block = client.input(16, 9);  // serial 16..20, firmware 21..24
  REQUIRE(block.size() == 9);
  CHECK(string_at(block, 0, 10) == "20240917  ");
  CHECK(string_at(block, 5, 8) == "1.02    ");
}

TEST_CASE("a Modbus RTU device that answers again after being offline has its identity read again") {
  RtuPlant plant;
  REQUIRE_MESSAGE(plant.gateway.wait_listening(plant.port), plant.gateway.log());
  REQUIRE(wait_api(plant.http_port, "\"serial\":\"20240917\"").find("20240917") != std::string::npos);
  // The device falls silent, and another one (serial 777, firmware 2.00) takes its place.
  plant.sim.call([](modbus_rtu::RtuSimulator& sim) { sim.device(kSlave)->faults().silent = 1000000; });
  const std::string offline = wait_api(plant.http_port, "\"online\":false");
  REQUIRE_MESSAGE(offline.find("\"online\":false") != std::string::npos, offline);
  plant.sim.call([](modbus_rtu::RtuSimulator& sim) {
    modbus_rtu::SimulatedDevice& device = *sim.device(kSlave);
    device.holding()[1] = 777;  // CDAB: the low word first
    device.holding()[2] = 0;
    device.holding()[3] = 200;
    device.faults().silent = 0;
  });
  const std::string identified = wait_api(plant.http_port, "\"serial\":\"777\"");
  INFO(identified);
  CHECK(identified.find("\"serial\":\"777\",\"firmware\":\"2.00\"") != std::string::npos);
  // Online once a measurement followed the identity read (PolledSensorDriver::poll), which the
  // status copy may see apart.
  const std::string back = wait_api(plant.http_port, "\"online\":true");
  INFO(back);
  CHECK(back.find("\"online\":true") != std::string::npos);
  CHECK(back.find("\"serial\":\"777\"") != std::string::npos);
}
