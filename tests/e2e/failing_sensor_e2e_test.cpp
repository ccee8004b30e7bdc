// One failing sensor never takes its line with it (docs/operations.md, "One failing sensor never
// takes its line"): build/tiltgate with every timing key at its default serves a shared line of
// simulated sensors while one or two of them fall silent, answer garbage, answer late, answer
// NAK, collide or are written to, or while the tty goes away and comes back; a PLC reading every
// unit every 30 ms (tests/e2e/support/plc_watch.h) must see each healthy neighbour online,
// fresh, its angles readable and its own, and no reading older than its stale_ms, throughout.
#include <doctest/doctest.h>

#include <chrono>
#include <climits>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/plc_watch.h"
#include "e2e/support/shared_line_plant.h"
#include "rieker/simulator.h"
#include "spectron/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
using rieker::RiekerSimulator;
using spectron::DynaSimulator;

namespace {

using Clock = std::chrono::steady_clock;
using RiekerLine = SharedLinePlant<SimulatorThread>;
using DynaLine = SharedLinePlant<DynaSimulatorThread>;

constexpr std::int64_t kStaleMs = 1000;  // stale_ms's default with poll_ms 100

// H6 sensors at 11, 12, ... (unit N at 10 + N), paced at `baud`; `colliding` units get a
// second simulated sensor at their address, so both answer every request to it.
rieker::RiekerSimulatorOptions rieker_sensors(int count, std::uint32_t baud,
                                              std::vector<int> colliding = {}) {
  rieker::RiekerSimulatorOptions options;
  options.pace_baud = baud;
  for (int unit = 1; unit <= count; ++unit) {
    rieker::SimulatedSensorOptions sensor;
    sensor.model = rieker::Model::h6;
    sensor.address = std::uint16_t(10 + unit);
    sensor.angle_x = unit;
    sensor.angle_y = -unit;
    sensor.serial = fmt::format("96{:04}", unit);
    options.sensors.push_back(sensor);
  }
  for (int unit : colliding) options.sensors.push_back(options.sensors.at(unit - 1));
  return options;
}

struct RiekerPlant : RiekerLine {
  explicit RiekerPlant(int count = 6, std::uint32_t baud = 125000, std::vector<int> colliding = {})
      : RiekerLine(rieker_sensors(count, baud, colliding), count,
                   fmt::format("protocol = \"rieker\"\nbaud = {}", baud), "h6",
                   [](int) { return std::string(); }, 11, colliding) {}

  // Sensor `unit`'s faults (the first simulated sensor at its address).
  template <class Fault>
  void fault(int unit, Fault fault) {
    sim->call([unit, fault](RiekerSimulator& s) {
      fault(s.sensor(std::size_t(unit - 1)).faults());
      return 0;
    });
  }
  void silence(int unit) {
    fault(unit, [](rieker::SensorFaults& f) { f.silent = INT_MAX; });
  }
};

// Dyna modules 1, 2, ... (unit N is module N) on a Spectron line at 28800 baud, paced.
spectron::DynaSimulatorOptions dyna_modules(int count, spectron::Protocol protocol) {
  spectron::DynaSimulatorOptions options;
  options.protocol = protocol;
  options.pace_baud = 28800;
  for (int unit = 1; unit <= count; ++unit) {
    spectron::SimulatedDynaOptions module;
    module.address = std::uint8_t(unit);
    module.serial = std::uint16_t(5000 + unit);
    module.counts = std::int16_t(100 * unit);
    options.sensors.push_back(module);
  }
  return options;
}

struct DynaPlant : DynaLine {
  DynaPlant(int count, spectron::Protocol protocol, std::string_view bus_protocol)
      : DynaLine(dyna_modules(count, protocol), count,
                 fmt::format("protocol = \"{}\"\nbaud = 28800", bus_protocol), "dyna",
                 [](int) { return std::string("counts_per_degree = 100"); }, 1) {}

  template <class Fault>
  void fault(int unit, Fault fault) {
    sim->call([unit, fault](DynaSimulator& s) {
      fault(s.sensor(std::size_t(unit - 1)).faults());
      return 0;
    });
  }
};

// Every healthy unit stayed online and fresh, its angle always readable and its own (unit N
// reads N degrees on every line here), no reading older than stale_ms: what a PLC relies on
// while a neighbour fails.
void check_untouched(const PlcWatch& watch, const std::vector<int>& healthy) {
  for (int unit : healthy) {
    const UnitSeen seen = watch.seen(unit);
    CAPTURE(unit);
    CHECK(seen.reads >= 50);
    CHECK(seen.angle_min == doctest::Approx(unit));
    CHECK(seen.angle_max == doctest::Approx(unit));
    CHECK(seen.offline == 0);
    CHECK(seen.stale == 0);
    CHECK(seen.unavailable == 0);
    CHECK(seen.worst_age_ms < kStaleMs);
  }
}

// The failing unit itself still reads as its failure says: offline, its angle 0x0B.
void check_detected(const PlcWatch& watch, int unit) {
  const UnitSeen seen = watch.seen(unit);
  CAPTURE(unit);
  CHECK(seen.offline > 0);
  CHECK(seen.unavailable > 0);
  CHECK(seen.last_exception == 0x0B);
}

// `watch` reads on for a second, then `fault` comes, then 7 s more, and stops.
template <class Fault>
void watch_through(PlcWatch& watch, Fault fault) {
  std::this_thread::sleep_for(1s);
  fault();
  std::this_thread::sleep_for(7s);
  watch.stop();
}

// One write of `value` to holding register 0 (filter) of `unit`: how long its answer took and
// the exception it carried (0: done).
struct WriteAnswer {
  std::chrono::milliseconds took;
  int exception;
  Clock::time_point sent;
};

WriteAnswer write_filter(ModbusClient& client, int unit, std::uint16_t value) {
  client.unit(unit);
  const auto sent = Clock::now();
  const bool done = client.write(0, value);
  const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - sent);
  return {took, done ? 0 : client.exception(), sent};
}

}  // namespace

TEST_CASE("a sensor that falls silent leaves its five neighbours on the line online and fresh") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] { plant.silence(3); });
  check_untouched(watch, plant.units_but({3}));
  check_detected(watch, 3);
}

TEST_CASE("a sensor that answers with a broken CRC leaves its five neighbours untouched") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.fault(3, [](rieker::SensorFaults& f) { f.corrupt_crc = INT_MAX; });
  });
  check_untouched(watch, plant.units_but({3}));
  check_detected(watch, 3);
}

TEST_CASE("a sensor that answers 300 ms late leaves its neighbours untouched and stays online") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.fault(3, [](rieker::SensorFaults& f) { f.reply_delay = 300ms; });
  });
  check_untouched(watch, plant.units_but({3}));
  // Within max_timeout_ms: its reply wait adapts, it keeps answering, status bit 5 says so.
  ModbusClient client(plant.port, 3);
  const auto status = client.input(6, 1);
  REQUIRE(status.size() == 1);
  CHECK((status[0] & 0x21) == 0x21);  // online, answers late
  CHECK(watch.seen(3).worst_age_ms < kStaleMs);
}

TEST_CASE("a gateway stopped mid-exchange logs no sensor as having stopped answering") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  // Its replies 300 ms late: it stays online, and the line is on the wire with it most of the
  // time, so the stop almost surely cuts one of its exchanges off.
  plant.fault(3, [](rieker::SensorFaults& f) { f.reply_delay = 300ms; });
  std::this_thread::sleep_for(1500ms);
  watch.stop();
  ModbusClient client(plant.port, 3);
  const auto status = client.input(6, 1);
  REQUIRE(status.size() == 1);
  REQUIRE((status[0] & 0x21) == 0x21);  // online, answers late
  CHECK(plant.gateway->terminate() == 0);
  const std::string log = plant.gateway->log();
  INFO(log);
  CHECK(log.find("shutting down") != std::string::npos);
  CHECK(log.find("stopped answering") == std::string::npos);
}

TEST_CASE("a sensor that answers NAK 5 (busy) to everything leaves its five neighbours untouched") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.fault(3, [](rieker::SensorFaults& f) { f.busy = INT_MAX; });
  });
  check_untouched(watch, plant.units_but({3}));
  CHECK(watch.seen(3).unavailable > 0);  // it answers, but brings no reading: stale, 0x0B
}

TEST_CASE("a silent sensor written once a second: writes answered at once, neighbours untouched") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  ModbusClient writer(plant.port, 3);
  ModbusClient neighbour_writer(plant.port, 5);
  std::this_thread::sleep_for(1s);
  const WriteAnswer healthy_line = write_filter(neighbour_writer, 5, 3);
  plant.silence(3);
  std::vector<WriteAnswer> to_silent, to_neighbour;
  for (int second = 0; second < 8; ++second) {
    const auto start = Clock::now();
    to_silent.push_back(write_filter(writer, 3, std::uint16_t(2 + second % 3)));
    to_neighbour.push_back(write_filter(neighbour_writer, 5, std::uint16_t(2 + second % 3)));
    std::this_thread::sleep_until(start + 1s);
  }
  watch.stop();
  check_untouched(watch, plant.units_but({3}));
  check_detected(watch, 3);
  CHECK(healthy_line.exception == 0);
  const auto offline_since = watch.first_offline(3);
  REQUIRE(offline_since.has_value());
  for (const WriteAnswer& write : to_silent) {
    CAPTURE(write.took.count());
    CHECK(write.exception == 0x0B);
    CHECK(write.took <= 3000ms);  // write_timeout_ms
    // Known offline when it arrived: one reply wait (timeout_ms 50) at most.
    if (write.sent > *offline_since) CHECK(write.took <= 100ms);
  }
  for (const WriteAnswer& write : to_neighbour) {
    CAPTURE(write.took.count());
    CHECK(write.exception == 0);
    // As on a healthy line, plus one late-reply guard (450 ms) and its reply wait at most.
    CHECK(write.took <= healthy_line.took + 500ms + 100ms);
  }
}

TEST_CASE("two failing sensors at once, one silent and one colliding, leave the five others untouched") {
  RiekerPlant plant(7, 125000, {5});  // unit 5's address is answered twice, garbled
  // The pair collides from the start: unit 5 never reads; the others must all the same.
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] { plant.silence(2); });
  check_untouched(watch, plant.units_but({2, 5}));
  check_detected(watch, 2);
  check_detected(watch, 5);
}

TEST_CASE("a tty that returns: its sensors read fresh at the first poll after the reopen") {
  RiekerPlant plant;
  PlcWatch watch(plant.port, plant.units_but({}));
  std::this_thread::sleep_for(500ms);
  plant.sim->call([](RiekerSimulator& s) {
    s.unplug();
    return 0;
  });
  const auto unplugged = Clock::now();
  std::this_thread::sleep_for(3s);
  // The poll that finds the tty gone takes every sensor of the bus offline: their angles
  // answer 0x0B from then on, without waiting for stale_ms (1 s) as for a silent sensor.
  for (const int unit : plant.units_but({})) {
    const auto unavailable = watch.first_unavailable_since(unit, unplugged);
    REQUIRE(unavailable.has_value());
    CHECK(watch.seen(unit).last_exception == 0x0B);
    MESSAGE("unit ", unit, ": 0x0B ",
            std::chrono::duration_cast<std::chrono::milliseconds>(*unavailable - unplugged).count(),
            " ms after the tty went");
    CHECK(*unavailable - unplugged < 1s);
  }
  REQUIRE(plant.sim->call([](RiekerSimulator& s) { return s.replug().has_value(); }));
  // The gateway logs the reopen; what reads fresh after it counts from there.
  std::optional<Clock::time_point> reopened;
  const auto give_up = Clock::now() + 15s;
  while (!reopened && Clock::now() < give_up) {
    if (plant.gateway->log().find("reopened") != std::string::npos) reopened = Clock::now();
    else std::this_thread::sleep_for(5ms);
  }
  REQUIRE_MESSAGE(reopened.has_value(), plant.gateway->log());
  std::this_thread::sleep_for(2s);
  watch.stop();
  const auto fresh = watch.all_fresh_since(*reopened);
  REQUIRE(fresh.has_value());
  // The first poll after the reopen: within a poll period (100 ms), with room for a slow
  // machine; before, the dead-sensor back-off added up to 5 s on top.
  CHECK(*fresh - *reopened <= 500ms);
}

TEST_CASE("on a 9600-baud line of 10 sensors, one silent and one with a broken CRC take nothing from the eight others") {
  RiekerPlant plant(10, 9600);
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.silence(4);
    plant.fault(7, [](rieker::SensorFaults& f) { f.corrupt_crc = INT_MAX; });
  });
  check_untouched(watch, plant.units_but({4, 7}));
  check_detected(watch, 4);
  check_detected(watch, 7);
}

TEST_CASE("on a 9600-baud line of 10 sensors, one silent and one 300 ms late take nothing from the eight others") {
  RiekerPlant plant(10, 9600);
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.silence(2);
    plant.fault(9, [](rieker::SensorFaults& f) { f.reply_delay = 300ms; });
  });
  check_untouched(watch, plant.units_but({2, 9}));
  check_detected(watch, 2);
}

TEST_CASE("a Dyna module that falls silent on a Modbus-ASCII line leaves its five neighbours untouched") {
  DynaPlant plant(6, spectron::Protocol::modbus_ascii, "spectron-modbus");
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.fault(3, [](spectron::DynaFaults& f) { f.silent = INT_MAX; });
  });
  check_untouched(watch, plant.units_but({3}));
  check_detected(watch, 3);
}

// 9-bit replies carry no address: only the late-reply guard keeps a late one from being taken
// for the next module's, which the neighbours' own angles would show.
TEST_CASE("a Dyna module that answers 300 ms late on a 9-bit line leaves its five neighbours untouched") {
  DynaPlant plant(6, spectron::Protocol::nine_bit, "spectron-9bit");
  PlcWatch watch(plant.port, plant.units_but({}));
  watch_through(watch, [&] {
    plant.fault(4, [](spectron::DynaFaults& f) { f.reply_delay = 300ms; });
  });
  check_untouched(watch, plant.units_but({4}));
}
