// A Modbus read allocates nothing once its connection is open (issue 29; docs/performance.md,
// "The Modbus read path"): the gateway's real server, router and reader on loopback, with a
// fake sensor that has its reading and an aggregate unit over it, read by the libmodbus client
// (C: it never calls operator new, so every allocation counted is the gateway's). Counted over
// hundreds of reads of every kind, served on a worker pool's thread (as `tiltgate run`) and on
// the server's own thread (a server given no pool).
#include <doctest/doctest.h>
#include <modbus.h>

#include <chrono>
#include <cstdint>
#include <memory>

#include "alloc/allocation_count.h"
#include "unit/support/served_plant.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

constexpr std::uint8_t kUnit = 1;
constexpr std::uint8_t kAggregateUnit = 200;
constexpr int kRounds = 200;

// One fake H6 polled once (then not for an hour, so the bus thread sleeps while reads are
// counted), an aggregate of its angles, its router and a server; `tcp_threads` 0 gives the
// server no pool.
struct QuietPlant : ServedPlant {
  explicit QuietPlant(std::size_t tcp_threads) : ServedPlant(tcp_threads, false) {
    sensors.push_back(std::shared_ptr<GatewaySensor>(fake_sensor("s1", kUnit, 1, events, 1h)));
    scheduler.add(sensors.back());
    router.add(sensors.back());
    AggregateConfig config;
    config.unit_id = kAggregateUnit;
    config.points = {"angle_x", "angle_y", "status"};
    config.sensors = {"s1"};
    auto aggregate = make_gateway_aggregate(config, sensors);
    REQUIRE(aggregate.has_value());
    router.add(*aggregate);
    serve();
  }
};

// One round of every read: input registers (10 and all 38), holding registers, discrete
// inputs, a read past the map (exception 02), and the aggregate unit's registers. The number
// of replies that were not what they should be.
int read_round(modbus_t* ctx) {
  int wrong = 0;
  std::uint16_t words[125];
  std::uint8_t bits[16];
  modbus_set_slave(ctx, kUnit);
  if (modbus_read_input_registers(ctx, 0, 10, words) != 10) ++wrong;
  if (modbus_read_input_registers(ctx, 0, 38, words) != 38) ++wrong;
  if (modbus_read_registers(ctx, 0, 8, words) != 8) ++wrong;
  if (modbus_read_input_bits(ctx, 0, 7, bits) != 7) ++wrong;
  if (modbus_read_input_registers(ctx, 9000, 10, words) != -1 || errno != EMBXILADD) ++wrong;
  modbus_set_slave(ctx, kAggregateUnit);
  if (modbus_read_input_registers(ctx, 0, 5, words) != 5) ++wrong;  // x, y: 2 words each
  return wrong;
}

void check_reads_allocate_nothing(std::size_t tcp_threads) {
  QuietPlant plant(tcp_threads);
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", plant.port);
  REQUIRE(ctx != nullptr);
  modbus_set_slave(ctx, kUnit);
  modbus_set_response_timeout(ctx, 5, 0);
  REQUIRE(modbus_connect(ctx) == 0);
  // The first reads grow the connection's buffers and the thread's recycled blocks.
  int wrong = 0;
  for (int i = 0; i < 5; ++i) wrong += read_round(ctx);
  // The accepting thread re-arms its accept (an allocation) after handing the connection on;
  // a loaded machine can hold it back until reads are being counted.
  plant.wait_for_bus_thread();
  const std::uint64_t before = allocations_so_far();
  for (int i = 0; i < kRounds; ++i) wrong += read_round(ctx);
  const std::uint64_t after = allocations_so_far();
  modbus_close(ctx);
  modbus_free(ctx);
  CHECK(wrong == 0);
  INFO("reads: ", kRounds * 6);
  CHECK(after - before == 0);
}

}  // namespace

TEST_CASE("a read allocates nothing once its connection is open, served on a TCP thread") {
  check_reads_allocate_nothing(1);
}

TEST_CASE("a read allocates nothing once its connection is open, on a server without a pool") {
  check_reads_allocate_nothing(0);
}

TEST_CASE("the counting allocator counts") {
  // Else the two above could pass on a program whose operator new is not the counting one.
  const std::uint64_t before = allocations_so_far();
  auto held = std::make_unique<int>(1);
  CHECK(allocations_so_far() == before + 1);
  CHECK(*held == 1);
}
