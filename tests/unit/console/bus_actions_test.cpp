// The web console's scan runs in the gateway (console/bus_actions.h): whatever becomes of it, it
// ends, and its bus takes the next scan.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "console/bus_actions.h"
#include "unit/support/config_text.h"

namespace tiltgate {
namespace {

namespace asio = boost::asio;

struct TempConfig {
  std::string path;
  explicit TempConfig(std::string_view text) {
    char name[] = "/tmp/tiltgate-bus-actions-XXXXXX";
    const int fd = ::mkstemp(name);
    REQUIRE(fd >= 0);
    ::close(fd);
    path = name;
    std::ofstream(path) << text;
  }
  ~TempConfig() { std::remove(path.c_str()); }
};

// Actions on a config whose bus "line1" the gateway serves (with no scheduler: the scans here
// never reach the line).
BusActionSetup served_line1(asio::io_context& io, const std::string& config_path) {
  BusActionSetup setup;
  setup.config_path = config_path;
  setup.gateway_executor = io.get_executor();
  setup.served_bus = [](const std::string& name) -> std::optional<ServedBus> {
    if (name != "line1") return std::nullopt;
    ServedBus bus;
    bus.config.name = "line1";
    bus.config.port = "/dev/ttyUSB0";
    bus.config.protocol = "rieker-h";
    bus.config.baud = 125000;
    return bus;
  };
  setup.families = registered_families();
  return setup;
}

TEST_CASE("a scan that throws mid-way ends with its error, and the bus takes the next scan") {
  const TempConfig config{test::valid_plus("")};
  asio::io_context io;
  BusActionSetup setup = served_line1(io, config.path);
  int scans = 0;
  setup.scan = [&scans](CommissionBus&, const PreparedScan&, const EventSink& report,
                        const bool&) -> asio::awaitable<int> {
    ++scans;
    report(ProgressEvent{3, 10, 125000, {}});
    throw std::runtime_error("the engine broke");
    co_return 0;
  };
  BusActions actions(std::move(setup));
  unsigned status = 0;
  actions.start_scan("line1", ScanRequest{}, "alice", status);
  CHECK(status == 202);
  // While it runs, a second is refused.
  actions.start_scan("line1", ScanRequest{}, "alice", status);
  CHECK(status == 409);
  io.run();
  const auto state = actions.scan_state("line1");
  CHECK(state["running"] == false);
  REQUIRE(state["error"].is_string());
  CHECK(state["error"].get<std::string>().find("the engine broke") != std::string::npos);
  actions.start_scan("line1", ScanRequest{}, "alice", status);
  CHECK(status == 202);
  io.restart();
  io.run();
  CHECK(scans == 2);
}

TEST_CASE("a scan's found sensors are its tables, and its output the text a person reads") {
  const TempConfig config{test::valid_plus("")};
  asio::io_context io;
  BusActionSetup setup = served_line1(io, config.path);
  setup.scan = [](CommissionBus& bus, const PreparedScan&, const EventSink& report,
                  const bool&) -> asio::awaitable<int> {
    FoundSensor sensor;
    sensor.address = 7;
    sensor.baud = 125000;
    sensor.model = "h6";
    sensor.serial = "9600007";
    ScanFinishedEvent finished;
    finished.found = {sensor};
    finished.probes = 1;
    finished.tables = sensor_tables(bus.config(), finished.found, {});
    report(finished);
    co_return 0;
  };
  BusActions actions(std::move(setup));
  unsigned status = 0;
  actions.start_scan("line1", ScanRequest{}, "alice", status);
  REQUIRE(status == 202);
  io.run();
  const auto state = actions.scan_state("line1");
  CHECK(state["error"].is_null());
  CHECK(state["progress"] == 1);
  REQUIRE(state["found"].size() == 1);
  CHECK(state["found"][0]["address"] == 7);
  CHECK(state["found"][0]["serial"] == "9600007");
  CHECK(state["found"][0]["config"].get<std::string>().starts_with("[[sensor]]\n"));
  CHECK(state["output"].get<std::string>().find("1 sensor(s) found") != std::string::npos);
}

TEST_CASE("a scan of a bus the request cannot take is refused with the reason, not started") {
  const TempConfig config{test::valid_plus("")};
  asio::io_context io;
  BusActions actions(served_line1(io, config.path));
  unsigned status = 0;
  ScanRequest backwards;
  backwards.from = 300;
  const auto reply = actions.start_scan("line1", backwards, "alice", status);
  CHECK(status == 400);
  CHECK(reply["error"].get<std::string>().find("--from") != std::string::npos);
  CHECK(actions.scan_state("line1")["running"] == false);
}

}  // namespace
}  // namespace tiltgate
