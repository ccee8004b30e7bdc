// A sensor's setting changed by name through the gateway's write path (settings/setting_writer.h),
// as the console and Sparkplug's DCMD change one: a Gateway run in-process on a simulated
// Rieker H6 behind a pseudo-terminal, answered with the sensor's ACK (and the setting's value
// before), its NAK with the code, a time-out when it is silent, and a refusal of a value out of
// range before anything is sent.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "config/config_loader.h"
#include "gateway/gateway.h"
#include "rieker/simulator.h"
#include "settings/setting_writer.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/termios2_skip.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Result = SettingOutcome::Result;

namespace {

constexpr std::uint16_t kAddress = 223;

std::string config_text(const std::string& port) {
  return "[server]\nwrite_timeout_ms = 5000\n"
         "[[bus]]\nname = \"line1\"\nport = \"" + port + "\"\ntimeout_ms = 100\n"
         "[[sensor]]\nname = \"boom\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 223\n"
         "unit_id = 1\npoll_ms = 50\n";
}

// The gateway and its simulated sensor share one io_context, run by the test's thread.
struct Plant {
  boost::asio::io_context io;
  test::ScratchDir dir{"tiltgate-setting-writer"};
  std::optional<rieker::RiekerSimulator> sim;
  std::optional<Config> config;
  std::unique_ptr<Gateway> gateway;
  std::optional<SettingWriter> writer;

  Plant() {
    rieker::RiekerSimulatorOptions options;
    options.link_path = dir.path("ttyRS485");
    rieker::SimulatedSensorOptions sensor;
    sensor.address = kAddress;
    options.sensors = {sensor};
    sim.emplace(io, options);
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
    auto loaded = load_config_string(config_text(sim->link_path()), "test.toml",
                                     registered_families());
    REQUIRE(loaded.has_value());
    config = std::move(*loaded);
    test::skip_unless_settable(config->buses.front().baud);  // a Rieker bus: 125000 needs termios2
    config->server.listen = "127.0.0.1";
    config->server.port = 0;  // any free port: the test writes through the writer, not Modbus
    gateway = std::make_unique<Gateway>(io, *config, registered_families());
    const auto running = gateway->start();
    REQUIRE_MESSAGE(running.has_value(), running.error());
    writer.emplace(*gateway, registered_families());
    REQUIRE(wait_until([&] {
      const auto snapshot = gateway->sensors().front()->snapshot();
      return snapshot && snapshot->state.online && snapshot->state.reading.has_value();
    }));
  }
  ~Plant() {
    gateway->stop();
    sim->stop();
    io.stop();
    finish_stopped(io);
  }

  template <class Condition>
  bool wait_until(Condition done) {
    for (int i = 0; i < 200 && !done(); ++i) test::run_for(io, 20ms);
    return done();
  }
  SettingOutcome write(const std::string& setting, double value) {
    return test::run_coroutine(
        io, writer->write("boom", setting, value, WriteOrigin{"console", "alice"}));
  }
  rieker::SimulatedSensor& sensor() { return *sim->sensor_by_address(kAddress); }
};

}  // namespace

TEST_CASE("a setting written by name is answered after the sensor's ACK, with its value before") {
  Plant plant;
  const SettingOutcome first = plant.write("filter", 3);
  CHECK(first.result == Result::ack);
  CHECK_FALSE(first.old_value.has_value());  // a Rieker sensor reads no setting back
  CHECK(plant.sensor().filter() == 3);
  const SettingOutcome second = plant.write("filter", 5);
  CHECK(second.result == Result::ack);
  REQUIRE(second.old_value.has_value());
  CHECK(*second.old_value == 3);
  CHECK(plant.sensor().filter() == 5);
  CHECK(audit_result(second) == "ack");
}

TEST_CASE("a setting the sensor refuses is answered with its NAK and the code") {
  Plant plant;
  CHECK(plant.write("filter", 2).result == Result::ack);
  rieker::FunctionFaults refuse;
  refuse.nak = 1;
  refuse.nak_code = rieker::NakCode::data_invalid;
  plant.sensor().faults().by_function[rieker::Function::set_filter] = refuse;
  const SettingOutcome outcome = plant.write("filter", 4);
  CHECK(outcome.result == Result::nak);
  REQUIRE(outcome.code.has_value());
  CHECK(*outcome.code == std::uint8_t(rieker::NakCode::data_invalid));
  CHECK(outcome.detail.find("NAK 3") != std::string::npos);
  REQUIRE(outcome.old_value.has_value());
  CHECK(*outcome.old_value == 2);
  CHECK(audit_result(outcome) == "nak 0x03");
  CHECK(plant.sensor().filter() == 2);
}

TEST_CASE("a setting written to a silent sensor is answered with a time-out") {
  Plant plant;
  REQUIRE(plant.sim->command("silent 223").has_value());
  const SettingOutcome outcome = plant.write("zero_x", 1.5);
  CHECK(outcome.result == Result::timeout);
  CHECK(audit_result(outcome) == "timeout");
}

TEST_CASE("a value out of the setting's range is refused before anything is sent") {
  Plant plant;
  const std::uint64_t before = plant.sensor().requests_of(rieker::Function::set_filter);
  const SettingOutcome outcome = plant.write("filter", 9);
  CHECK(outcome.result == Result::refused);
  CHECK(outcome.detail == "the value is out of the setting's range");
  CHECK(plant.sensor().requests_of(rieker::Function::set_filter) == before);
  CHECK(plant.write("nonsense", 1).result == Result::refused);
  CHECK(plant.write("filter", 9).detail == "the value is out of the setting's range");
}
