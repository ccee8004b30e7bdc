// SIGHUP reload of build/tiltgate (docs/operations.md, "Reloading the configuration"), seen by one libmodbus
// client connection kept open throughout and by simulated Rieker sensors: an invalid file is
// refused and changes nothing; a valid one adds, changes and removes units without closing the
// connection; writes queued when the reload comes are carried out and answered truly.
#include <doctest/doctest.h>

#include <csignal>
#include <fmt/format.h>
#include <future>
#include <modbus/modbus.h>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

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

rieker::SimulatedSensorOptions sensor(std::uint16_t address, double x, double y) {
  rieker::SimulatedSensorOptions s;
  s.model = rieker::Model::h6;
  s.address = address;
  s.angle_x = x;
  s.angle_y = y;
  return s;
}

// One Rieker bus of four H6 sensors, at addresses 221 to 224; the files below configure some.
struct ReloadPlant {
  ReloadPlant() {
    rieker::RiekerSimulatorOptions options;
    options.sensors = {sensor(221, 1.5, -2.25), sensor(222, 10, 20), sensor(223, -30.5, 0),
                       sensor(224, 4, 5)};
    options.link_path = (dir.path() / "ttyUSB0").string();
    sim = std::make_unique<SimulatorThread>(options);
  }

  // A file: [server], `http`, bus "line1" (with `retries`), then `sensors`.
  std::string file(const std::string& server_more, const std::string& sensors, int retries = 0,
                   const std::string& http = "[http]\nenabled = false") const {
    return server_table(port, "writes = true\ncontrol_socket = \"\"\n" + server_more) + "\n" + http +
           "\n" +
           bus_table("line1", (dir.path() / "ttyUSB0").string(),
                     fmt::format("protocol = \"rieker\"\ntimeout_ms = 2500\nmax_timeout_ms = 2500\n"
                                 "retries = {}\nreopen_min_ms = 50\nreopen_max_ms = 200",
                                 retries)) +
           sensors;
  }

  void start(const std::string& text) {
    config = dir.write("plant.toml", text);
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"--log-level", "debug", "run", "--config", config.string()},
        dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
  }

  // Writes `text` over the file, sends SIGHUP and waits for the gateway to log `outcome`
  // one more time than before.
  void reload(const std::string& text, const std::string& outcome) {
    const std::size_t before = count(gateway->log(), outcome);
    dir.write("plant.toml", text);
    REQUIRE(gateway->signal(SIGHUP));
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    while (count(gateway->log(), outcome) == before && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(20ms);
    REQUIRE_MESSAGE(count(gateway->log(), outcome) > before, gateway->log());
  }

  static std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  }

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::filesystem::path config;
  std::unique_ptr<GatewayProcess> gateway;
};

std::string h6_sensor(const std::string& name, int address, int unit_id, int poll_ms,
                      const std::string& more = "") {
  return sensor_table(name, "line1", "h6", address, unit_id,
                      fmt::format("poll_ms = {}\nstale_ms = 2000\n{}", poll_ms, more));
}

// Reads `count` input registers at `address` of `unit` until they read, for up to 10 s.
std::vector<std::uint16_t> read_when_online(ModbusClient& client, int unit, int address,
                                            int count) {
  client.unit(unit);
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    auto words = client.input(address, count);
    if (!words.empty()) return words;
    std::this_thread::sleep_for(50ms);
  }
  return {};
}

bool accepts(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool connected = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return connected;
}

}  // namespace

TEST_CASE("SIGHUP: an invalid file is refused, a valid one applies, one connection throughout") {
  ReloadPlant plant;
  const std::string first = plant.file(
      "", h6_sensor("left", 221, 1, 50) + h6_sensor("right", 222, 2, 50) +
              h6_sensor("mast", 223, 3, 50));
  plant.start(first);
  ModbusClient client(plant.port, 1);
  const int socket = modbus_get_socket(client.raw());
  const auto left = read_when_online(client, 1, 0, 4);
  REQUIRE_MESSAGE(left.size() == 4, plant.gateway->log());
  const auto right = read_when_online(client, 2, 0, 4);
  REQUIRE(right.size() == 4);
  client.unit(3);
  REQUIRE(client.input(6, 1).size() == 1);  // mast's status register, in its built-in map

  {  // An invalid edit: every error logged, nothing changed, and `check` agrees.
    const std::string broken =
        plant.file("", h6_sensor("left", 221, 1, 50) + h6_sensor("right", 222, 2, 5) +
                           h6_sensor("mast", 223, 3, 50, "colour = \"red\"\n"));
    plant.reload(broken, "reload refused");
    const std::string log = plant.gateway->log();
    CHECK(log.find("reload refused: 2 error(s); still serving the configuration loaded at ") !=
          std::string::npos);
    const CommandResult check = run_tiltgate({"check", "--config", plant.config.string()});
    CHECK(check.exit_code != 0);
    std::istringstream lines(check.err);
    int errors = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.find("error(s); nothing started") != std::string::npos) continue;
      ++errors;
      CHECK_MESSAGE(log.find("error " + line) != std::string::npos, line);
    }
    CHECK(errors == 2);
    // The same connection reads the same units and values.
    client.unit(1);
    CHECK(client.input(0, 4) == left);
    client.unit(2);
    CHECK(client.input(0, 4) == right);
    client.unit(3);
    CHECK(client.input(6, 1).size() == 1);
  }

  {  // Then a valid edit: a unit added, one changed, one removed, on the same connection.
    // right (unit 2) goes; mast gets a new poll and a map without its status register; a new
    // sensor "spare" answers as unit 4; left is unchanged.
    const std::string second = plant.file(
        "", h6_sensor("left", 221, 1, 50) +
                h6_sensor("mast", 223, 3, 80,
                          "[sensor.map]\nextends = \"default\"\nremove = [\"status\"]\n") +
                h6_sensor("spare", 224, 4, 50));
    plant.reload(second, "configuration reloaded");
    const std::string log = plant.gateway->log();
    CHECK(log.find("buses kept: line1; reopened: -; added: -; removed: -. sensors kept: left; "
                   "changed: mast; added: spare; removed: right") != std::string::npos);
    const auto spare = read_when_online(client, 4, 0, 4);
    REQUIRE_MESSAGE(spare.size() == 4, plant.gateway->log());
    client.unit(3);
    CHECK(client.input(6, 1).empty());
    CHECK(client.exception() == 0x02);  // mast's new map has no register 6
    CHECK(read_when_online(client, 3, 0, 4).size() == 4);
    client.unit(2);
    CHECK(client.input(0, 4).empty());
    CHECK(client.exception() == 0x0A);  // as for any unit the gateway does not serve
    client.unit(1);
    CHECK(client.input(0, 4) == left);
    // Never reconnected: libmodbus would have needed a new socket (and recovery is off).
    CHECK(modbus_get_socket(client.raw()) == socket);
  }
  CHECK(plant.gateway->running());
}

// Debian 12's toml++ follows a dotted key recursively: a key of 40,000 parts overflowed its
// stack, so `check` died of SIGSEGV and a reload of such a file killed the gateway.
TEST_CASE("a key of 40000 dotted parts is an error at its line for check and for a reload") {
  ReloadPlant plant;
  const std::string good = plant.file("", h6_sensor("left", 221, 1, 50));
  plant.start(good);
  ModbusClient client(plant.port, 1);
  const auto left = read_when_online(client, 1, 0, 4);
  REQUIRE_MESSAGE(left.size() == 4, plant.gateway->log());
  std::string deep = "a";
  for (int i = 0; i < 40000; ++i) deep += ".a";
  for (const std::string& shape : {deep + " = 1\n", "[" + deep + "]\n", "x = { " + deep + " = 1 }\n"}) {
    CAPTURE(shape.substr(0, 12));
    plant.reload(good + "\n" + shape, "reload refused");
    const CommandResult check = run_tiltgate({"check", "--config", plant.config.string()});
    CHECK(check.exit_code == 1);  // an error, not a signal
    CHECK(check.err.find("a key of more than 64 dotted parts") != std::string::npos);
    CHECK(check.err.find("plant.toml:") != std::string::npos);
    CHECK(plant.gateway->running());
    client.unit(1);
    CHECK(client.input(0, 4) == left);
  }
}

TEST_CASE("SIGHUP: writes queued before the reload are carried out and answered truly") {
  ReloadPlant plant;
  // left answers Set Filter 1.5 s late, so its write holds the bus across the reload; right
  // refuses Set Filter (NAK). The writes behind left's wait in the bus's queue.
  plant.sim->call([](RiekerSimulator& s) {
    s.sensor(0).faults().by_function[rieker::Function::set_filter].delay = 1500ms;
    s.sensor(1).faults().by_function[rieker::Function::set_filter].nak = 100;
    return 0;
  });
  plant.start(plant.file("write_timeout_ms = 10000",
                         h6_sensor("left", 221, 1, 50) + h6_sensor("right", 222, 2, 50)));
  ModbusClient watcher(plant.port, 1);  // kept open across the reload
  REQUIRE_MESSAGE(read_when_online(watcher, 1, 0, 4).size() == 4, plant.gateway->log());
  REQUIRE(read_when_online(watcher, 2, 0, 4).size() == 4);

  auto write = [&](int unit, int address, std::vector<std::uint16_t> words) {
    return std::async(std::launch::async, [&plant, unit, address, words] {
      ModbusClient client(plant.port, unit);
      const bool ok = client.write(address, words);
      return ok ? 0 : client.exception() != 0 ? client.exception() : -1;
    });
  };
  auto slow_filter = write(1, 0, {6});  // on the wire for 1.5 s
  std::this_thread::sleep_for(200ms);
  auto zero_x = write(1, 1, {0x3F00, 0x0000});  // 0.5, queued behind it
  auto refused_filter = write(2, 0, {2});       // queued too; the sensor will NAK it
  std::this_thread::sleep_for(200ms);
  // The bus changes (retries), so it is reopened and left replaced; right is removed. The old
  // bus carries out the queued writes before it lets the tty go to the new one.
  plant.reload(plant.file("write_timeout_ms = 10000", h6_sensor("left", 221, 1, 70), 1),
               "configuration reloaded");
  CHECK(plant.gateway->log().find("buses kept: -; reopened: line1; added: -; removed: -. "
                                  "sensors kept: -; changed: left; added: -; removed: right") !=
        std::string::npos);

  CHECK(slow_filter.get() == 0);
  CHECK(zero_x.get() == 0);
  CHECK(refused_filter.get() == 0x03);  // the sensor's NAK, not a false success
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(0).filter(); }) == 6);
  CHECK(plant.sim->call([](RiekerSimulator& s) {
    return s.sensor(0).zero_offset(rieker::Axis::x);
  }) == 0.5);
  CHECK(plant.sim->call([](RiekerSimulator& s) { return s.sensor(1).filter(); }) ==
        rieker::kDefaultFilter);
  const std::string log = plant.gateway->log();
  // The reload came while the writes were queued: they were done after it.
  const auto reloaded = log.find("configuration reloaded");
  CHECK(log.find("left: wrote filter", reloaded) != std::string::npos);
  CHECK(log.find("left: wrote zero_x", reloaded) != std::string::npos);
  CHECK(log.find("right: write filter = 2 failed", reloaded) != std::string::npos);
  CHECK(plant.gateway->running());
  // The watcher's connection survived (left's new object reads once it was polled), and
  // unit 2 is gone.
  CHECK(read_when_online(watcher, 1, 0, 4).size() == 4);
  watcher.unit(2);
  CHECK(watcher.input(0, 4).empty());
  CHECK(watcher.exception() == 0x0A);
}

TEST_CASE("SIGHUP: a changed [http] table restarts the status API, kept sensors keep their history") {
  ReloadPlant plant;
  const std::uint16_t first_port = free_tcp_port();
  auto http = [](std::uint16_t port) {
    return http_table(port, "history_interval_ms = 100\nhistory_seconds = 60");
  };
  const std::string sensors = h6_sensor("left", 221, 1, 50) + h6_sensor("right", 222, 2, 50);
  plant.start(plant.file("", sensors, 0, http(first_port)));
  ModbusClient client(plant.port, 1);
  REQUIRE_MESSAGE(read_when_online(client, 1, 0, 4).size() == 4, plant.gateway->log());
  auto samples = [](std::uint16_t port) {
    return ReloadPlant::count(get(port, "/api/sensors/left/history").body, "\"t\":");
  };
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (samples(first_port) < 5 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(100ms);
  REQUIRE(samples(first_port) >= 5);

  // right goes, and the API moves to another port: left's graph comes along.
  const std::uint16_t second_port = free_tcp_port();
  plant.reload(plant.file("", h6_sensor("left", 221, 1, 50), 0, http(second_port)),
               "configuration reloaded");
  CHECK(plant.gateway->log().find("restarted: http") != std::string::npos);
  // A sensor less is no restart of a service the configuration does not have.
  const std::string reloaded = plant.gateway->log();
  const std::size_t restarted = reloaded.find("restarted: ");
  REQUIRE(restarted != std::string::npos);
  CHECK(reloaded.substr(restarted, reloaded.find('\n', restarted) - restarted) == "restarted: http");
  const std::size_t kept = samples(second_port);
  CHECK(kept >= 5);
  CHECK(get(second_port, "/api/sensors/right/history").status == 404);
  CHECK(get(second_port, "/api/sensors").body.find("\"right\"") == std::string::npos);
  CHECK_FALSE(accepts(first_port));
  // The Modbus connection was not touched.
  client.unit(1);
  CHECK(client.input(0, 4).size() == 4);
}

TEST_CASE("SIGHUP: a changed [http] table on the same port restarts the status API on that port") {
  ReloadPlant plant;
  const std::uint16_t http_port = free_tcp_port();
  auto http = [http_port](int history_seconds) {
    return http_table(http_port, fmt::format("history_seconds = {}", history_seconds));
  };
  const std::string sensors = h6_sensor("left", 221, 1, 50);
  plant.start(plant.file("", sensors, 0, http(60)));
  const std::string serving = "HTTP status API and metrics on";
  REQUIRE(ReloadPlant::count(plant.gateway->log(), serving) == 1);
  REQUIRE(get(http_port, "/healthz").status == 200);

  // The old server lets the port go on its own thread; the new one binds it then.
  plant.reload(plant.file("", sensors, 0, http(120)), "configuration reloaded");
  CHECK(plant.gateway->log().find("restarted: http") != std::string::npos);
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (ReloadPlant::count(plant.gateway->log(), serving) < 2 &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(20ms);
  const std::string log = plant.gateway->log();
  INFO("gateway log: " << log);
  REQUIRE(ReloadPlant::count(log, serving) == 2);
  CHECK(log.find("HTTP status API off") == std::string::npos);
  CHECK(log.find(fmt::format(":{}/", http_port), log.rfind(serving)) != std::string::npos);
  CHECK(get(http_port, "/healthz").status == 200);
  CHECK(plant.gateway->running());
}
