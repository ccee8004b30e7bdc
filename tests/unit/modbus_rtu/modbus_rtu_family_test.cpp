// The Modbus RTU family's descriptor as the config loader and the serial options take it: the
// bus framing (parity, stop_bits) and the t3.5 gap from the baud, slave ids 1..247, and its
// simulator factory's sensor list.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "config/config_loader.h"
#include "gateway/serial_options.h"
#include "modbus_rtu/example_profile.h"
#include "modbus_rtu/family.h"
#include "modbus_rtu/profile_reader.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const FamilyDescriptor* const kList[] = {&modbus_rtu::kFamily};

std::string rtu_config(std::string_view bus_keys, int address = 1) {
  return "[[bus]]\nname = \"rtu\"\nport = \"/dev/ttyUSB0\"\nprotocol = \"modbus-rtu\"\n" +
         std::string(bus_keys) + "\n[[sensor]]\nname = \"tilt\"\nbus = \"rtu\"\nmodel = " +
         "\"modbus-rtu\"\naddress = " + std::to_string(address) + "\nunit_id = 1\ndevice = \"" +
         std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml\"\n";
}

BusConfig load_bus(std::string_view bus_keys) {
  auto loaded = load_config_string(rtu_config(bus_keys), "rtu.toml", kList);
  REQUIRE_MESSAGE(loaded.has_value(),
                  (loaded ? std::string() : loaded.error().front().to_string()));
  return loaded->buses.at(0);
}

}  // namespace

TEST_CASE("a Modbus RTU bus defaults to 19200 baud 8E1 with the spec's fixed t3.5 above 19200") {
  const BusConfig bus = load_bus("");
  CHECK(bus.baud == 19200);
  CHECK(serial_options_from(kList, bus).framing == Framing::eight_even_one);
  CHECK(bus.gap == 2006us);  // 3.5 x 11 bits at 19200 baud, rounded up
  CHECK(load_bus("baud = 38400\n").gap == 1750us);
  CHECK(load_bus("baud = 230400\n").gap == 1750us);
}

TEST_CASE("a Modbus RTU bus's gap follows its framing's character length unless gap_us is set") {
  CHECK(load_bus("baud = 9600\n").gap == 4011us);                         // 11-bit characters
  CHECK(load_bus("baud = 9600\nparity = \"none\"\n").gap == 4011us);      // 8N2: 11 bits too
  CHECK(load_bus("baud = 9600\nparity = \"none\"\nstop_bits = 1\n").gap == 3646us);  // 10 bits
  CHECK(load_bus("baud = 9600\ngap_us = 5000\n").gap == 5000us);
  CHECK(serial_options_from(kList, load_bus("parity = \"odd\"\n")).framing ==
        Framing::eight_odd_one);
}

TEST_CASE("Modbus RTU slave ids are 1..247 and bauds the standard rates") {
  auto loaded = load_config_string(rtu_config("", 248), "rtu.toml", kList);
  REQUIRE_FALSE(loaded.has_value());
  CHECK(loaded.error().front().to_string().find("expected 1..247") != std::string::npos);
  auto odd_rate = load_config_string(rtu_config("baud = 125000\n"), "rtu.toml", kList);
  REQUIRE_FALSE(odd_rate.has_value());
  CHECK(odd_rate.error().front().key == "bus[0].baud");
}

TEST_CASE("the Modbus RTU simulator factory takes a list of slave ids") {
  boost::asio::io_context io;
  const SimulatorDescriptor& sim = modbus_rtu::kCommands.simulator;
  auto two = sim.make(io, SimulatorSetup{"modbus-rtu:1, modbus-rtu:7", "", "", 0});
  REQUIRE(two.has_value());
  CHECK((*two)->sensor_count() == 2);
  CHECK_FALSE(sim.make(io, SimulatorSetup{"modbus-rtu:248", "", "", 0}).has_value());
  CHECK_FALSE(sim.make(io, SimulatorSetup{"h6:1", "", "", 0}).has_value());
  CHECK_FALSE(sim.make(io, SimulatorSetup{"modbus-rtu:3,modbus-rtu:3", "", "", 0}).has_value());
}

TEST_CASE("the Modbus RTU demo reads slave 1 of its simulator through the example profile") {
  const DemoBus& demo = modbus_rtu::kCommands.demo;
  REQUIRE(demo.sensors.size() == 1);
  const DemoSensor& sensor = demo.sensors[0];
  CHECK(sensor.address == 1);
  CHECK(demo_simulator_setup(modbus_rtu::kCommands).sensors == "modbus-rtu:1");
  REQUIRE(sensor.files.size() == 1);
  CHECK(sensor.files[0].key == "device");
  // Compiled in from the example at build time: the demo serves the example itself.
  const std::string example_path =
      std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";
  std::ifstream example(example_path, std::ios::binary);
  std::ostringstream text;
  text << example.rdbuf();
  CHECK(sensor.files[0].contents == text.str());
  CHECK(sensor.files[0].contents == modbus_rtu::kExampleInclinometerProfile);
  CHECK(modbus_rtu::parse_device_profile(sensor.files[0].contents, "demo").has_value());
}
