// A Modbus TCP device read by a gateway (protocol "modbus-tcp", model "modbus-tcp"): the device
// is a first build/tiltgate serving an RTU inclinometer (slave 17, unit 3) from the RTU simulator
// over Modbus TCP, with pass_through = [30, 32] to a simulated device at slave 30. A second
// build/tiltgate has a bus with port = "tcp://127.0.0.1:PORT" on the first one's Modbus TCP port
// and a sensor at address 3 read through examples/devices/tiltgate-unit.toml. A libmodbus client
// of the second gateway sees the first one's angles, and its pass-through unit 30 reaches the
// device behind the first gateway (two hops: MBAP, then RTU). `tiltgate scan` over the same URL
// finds the first gateway's units and nothing where it answers 0x0A (no route for the unit id)
// or 0x0B (a passed-through unit nobody answers), and `tiltgate info` asks a unit's function 43
// over it.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <fmt/format.h>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/mixed_plant.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr int kFarUnit = 3;     // the inclinometer's unit on the first gateway
constexpr int kNearUnit = 5;    // the same sensor's unit on the second
constexpr int kPassedUnit = 30; // the device behind both gateways' pass-through
constexpr int kSilentUnit = 32; // passed through by the first gateway, no device there
constexpr std::size_t kRegisters = 8;

// An example device profile: examples/devices/NAME.toml.
std::string example(std::string_view name) {
  return fmt::format("{}/examples/devices/{}.toml", TILTGATE_SOURCE_DIR, name);
}

// The device's Modbus TCP port as a bus's port.
std::string tcp_url(std::uint16_t port) { return fmt::format("tcp://127.0.0.1:{}", port); }

struct TwoGateways {
  TwoGateways()
      : sim(simulator_options(dir)),
        device_gateway({"--log-level", "debug", "run", "--config", device_config().string()},
                       dir.path()) {
    REQUIRE_MESSAGE(device_gateway.wait_listening(device_port), device_gateway.log());
    reader.emplace(std::vector<std::string>{"--log-level", "debug", "run", "--config",
                                            reader_config().string()},
                   dir.path());
    REQUIRE_MESSAGE(reader->wait_listening(reader_port), reader->log());
  }

  static modbus_rtu::RtuSimulatorOptions simulator_options(const TempDir& dir) {
    modbus_rtu::RtuSimulatorOptions options;
    options.devices.push_back(modbus_rtu::rtu_inclinometer(17));
    modbus_rtu::set_inclinometer_angles(options.devices.back(), 12.5, -3.25);
    modbus_rtu::SimulatedDevice device(kPassedUnit, kRegisters, kRegisters);
    for (std::size_t i = 0; i < kRegisters; ++i) device.holding()[i] = std::uint16_t(1000 + i);
    options.devices.push_back(std::move(device));
    options.link_path = (dir.path() / "ttyRtu").string();
    return options;
  }

  // The first gateway: the Modbus TCP device.
  std::filesystem::path device_config() const {
    return dir.write(
        "device.toml",
        server_table(device_port) +
            bus_table("rtu-line", (dir.path() / "ttyRtu").string(),
                      fmt::format("protocol = \"modbus-rtu\"\nbaud = 19200\ntimeout_ms = 50\n"
                                  "retries = 0\npass_through = [{}, {}]",
                                  kPassedUnit, kSilentUnit)) +
            sensor_table("boom", "rtu-line", "modbus-rtu", 17, kFarUnit,
                         fmt::format("poll_ms = 50\ndevice = \"{}\"",
                                     example("rtu-inclinometer"))));
  }

  // The second gateway: reads the first one over Modbus TCP.
  std::filesystem::path reader_config() const {
    return dir.write(
        "reader.toml",
        server_table(reader_port) +
            bus_table("far", tcp_url(device_port),
                      fmt::format("protocol = \"modbus-tcp\"\ntimeout_ms = 500\n"
                                  "pass_through = [{}]",
                                  kPassedUnit)) +
            sensor_table("far-boom", "far", "modbus-tcp", kFarUnit, kNearUnit,
                         fmt::format("poll_ms = 50\ndevice = \"{}\"", example("tiltgate-unit"))));
  }

  TempDir dir;
  std::uint16_t device_port = free_tcp_port();
  std::uint16_t reader_port = free_tcp_port();
  RtuSimulatorThread sim;
  GatewayProcess device_gateway;
  std::optional<GatewayProcess> reader;
};

// Input registers 0..6 (angles as float32 and cdeg, status) once the unit is online with a
// reading, as read through `client`.
std::vector<std::uint16_t> online_block(ModbusClient& client) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  std::vector<std::uint16_t> words;
  while (std::chrono::steady_clock::now() < deadline) {
    words = client.input(0, 7);
    if (words.size() == 7 && (words[6] & 0x01) == 0x01) return words;
    std::this_thread::sleep_for(50ms);
  }
  return words;
}

}  // namespace

TEST_CASE("a gateway reads another gateway's unit as a Modbus TCP device and sees its angles") {
  TwoGateways plant;
  ModbusClient far(plant.device_port, kFarUnit);
  ModbusClient near(plant.reader_port, kNearUnit);
  const auto far_words = online_block(far);
  REQUIRE_MESSAGE(far_words.size() == 7, plant.device_gateway.log());
  const auto near_words = online_block(near);
  INFO(plant.reader->log());
  REQUIRE(near_words.size() == 7);
  CHECK((near_words[6] & 0x01) == 0x01);
  // angle_x, angle_y (float32) and their hundredths: the far unit's, 12.5 and -3.25 degrees.
  CHECK(std::vector<std::uint16_t>(near_words.begin(), near_words.begin() + 6) ==
        std::vector<std::uint16_t>(far_words.begin(), far_words.begin() + 6));
  CHECK(near_words[4] == 1250);
  CHECK(std::int16_t(near_words[5]) == -325);
  // Model code (input 37): the reading gateway's sensor is a Modbus TCP device.
  CHECK(near.input(37, 1) == std::vector<std::uint16_t>{5});
}

TEST_CASE("pass-through on a modbus-tcp bus reaches the device behind the far gateway") {
  TwoGateways plant;
  ModbusClient client(plant.reader_port, kPassedUnit);
  INFO(plant.reader->log());
  const auto holding = client.holding(0, kRegisters);
  REQUIRE(holding.size() == kRegisters);
  for (std::size_t i = 0; i < kRegisters; ++i) CHECK(holding[i] == 1000 + i);
  // Past the device's registers: the device's own 0x02, relayed through both gateways.
  CHECK(client.holding(6, 4).empty());
  CHECK(client.exception() == 0x02);
}

TEST_CASE("scan over tcp:// finds the far units, none where the gateway answers 0x0A or 0x0B") {
  TwoGateways plant;
  const std::string config_out = (plant.dir.path() / "scanned.toml").string();
  const auto scan =
      run_tiltgate({"scan", "--port", tcp_url(plant.device_port), "--protocol", "modbus-tcp",
                    "--probe-timeout-ms", "1000", "--device", example("tiltgate-unit"),
                    "--config-out", config_out});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  // Found as Modbus TCP devices, on a bus with no rate: the written configuration checks as
  // it is (a modbus-tcp bus refuses `baud`, and a modbus-rtu model).
  CHECK(scan.out.find(" modbus-tcp ") != std::string::npos);
  CHECK(scan.out.find("modbus-rtu") == std::string::npos);
  const auto checked = run_tiltgate({"check", "--config", config_out});
  INFO(checked.out << checked.err);
  CHECK(checked.exit_code == 0);
  // Unit 3 is the inclinometer; unit 30 the passed-through device, which refuses the profile's
  // read (it has 8 registers): an exception from it is a device there. Every other unit id of
  // the first gateway answers 0x0A, and unit 32 (passed through, nobody at slave 32) 0x0B.
  CHECK(scan.out.find("2 sensor(s) found") != std::string::npos);
  CHECK(scan.out.find("found: 3, 30;") != std::string::npos);
}

TEST_CASE("a modbus-rtu sensor on a modbus-tcp bus is refused: each model has its protocol") {
  TempDir dir;
  const std::string config = (dir.path() / "wrong-model.toml").string();
  std::ofstream(config) << "[[bus]]\nname = \"far\"\nport = \"tcp://127.0.0.1:1502\"\n"
                           "protocol = \"modbus-tcp\"\n\n[[sensor]]\nname = \"boom\"\n"
                           "bus = \"far\"\nmodel = \"modbus-rtu\"\naddress = 3\nunit_id = 1\n"
                           "device = \""
                        << example("tiltgate-unit") << "\"\n";
  const auto checked = run_tiltgate({"check", "--config", config});
  INFO(checked.out << checked.err);
  CHECK(checked.exit_code != 0);
  CHECK((checked.out + checked.err).find("model \"modbus-rtu\" needs a modbus-rtu bus") !=
        std::string::npos);
}

TEST_CASE("info over tcp:// without a profile asks the far unit's identification over MBAP") {
  TwoGateways plant;
  const auto info = run_tiltgate({"info", "--port", tcp_url(plant.device_port), "--protocol",
                                  "modbus-tcp", "--address", std::to_string(kFarUnit)});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  // The first gateway's function 43 for its Modbus RTU inclinometer.
  CHECK(info.out.find("vendor:     generic\n") != std::string::npos);
  CHECK(info.out.find("product:    Modbus RTU device\n") != std::string::npos);
}
