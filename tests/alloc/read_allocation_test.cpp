// A Modbus read allocates nothing once its connection is open (issue 29; docs/performance.md,
// "The Modbus read path"): the gateway's real server, router and reader on loopback, with a
// fake sensor that has its reading, read by the libmodbus client (C: it never calls operator
// new, so every allocation counted is the gateway's). Counted over hundreds of reads of every
// kind the reader answers at once, served on a TCP worker thread (the default) and on the
// buses' own thread (`threads = 1`).
#include <doctest/doctest.h>
#include <modbus.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <thread>

#include "alloc/allocation_count.h"
#include "gateway/bus_scheduler.h"
#include "gateway/request_router.h"
#include "modbus_tcp/modbus_tcp_server.h"
#include "modbus_tcp/tcp_worker_pool.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

constexpr std::uint8_t kUnit = 1;
constexpr int kRounds = 200;

// One fake H6 polled once (then not for an hour, so the bus thread sleeps while reads are
// counted), its router and a server; `tcp_threads` 0 serves on the buses' thread.
struct QuietPlant {
  explicit QuietPlant(std::size_t tcp_threads) {
    if (tcp_threads > 0) workers = std::make_unique<TcpWorkerPool>(tcp_threads);
    sensor = std::shared_ptr<GatewaySensor>(fake_sensor("s1", kUnit, 1, events, 1h));
    scheduler.add(sensor);
    router.add(sensor);
    ModbusServerOptions options;
    options.listen = "127.0.0.1";
    options.port = 0;
    server = std::make_unique<ModbusTcpServer>(io.get_executor(), router, options, workers.get());
    REQUIRE(server->start().has_value());
    port = server->local_port();
    asio::co_spawn(io, scheduler.run(), asio::detached);
    bus_thread = std::thread([this] { io.run(); });
    while (!sensor->snapshot() || !sensor->snapshot()->state.reading)
      std::this_thread::sleep_for(1ms);
  }

  ~QuietPlant() {
    std::promise<void> stopped;
    asio::post(io, [&] {
      router.stop();
      server->stop();
      scheduler.stop();
      stopped.set_value();
    });
    stopped.get_future().wait();
    if (workers) workers->stop();
    guard.reset();
    io.stop();
    bus_thread.join();
  }

  std::unique_ptr<TcpWorkerPool> workers;  // before io, as in gateway_threads_test.cpp
  asio::io_context io;
  asio::executor_work_guard<asio::io_context::executor_type> guard{io.get_executor()};
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  RequestRouter router{io.get_executor(), RouterOptions{false, WordOrder::big, 3000ms}};
  BusEvents events;
  std::shared_ptr<GatewaySensor> sensor;
  std::unique_ptr<ModbusTcpServer> server;
  std::uint16_t port = 0;
  std::thread bus_thread;
};

// One round of every read the reader answers at once: input registers (10 and all 38),
// holding registers, discrete inputs, and a read past the map (exception 02). The number of
// replies that were not what they should be.
int read_round(modbus_t* ctx) {
  int wrong = 0;
  std::uint16_t words[125];
  std::uint8_t bits[16];
  if (modbus_read_input_registers(ctx, 0, 10, words) != 10) ++wrong;
  if (modbus_read_input_registers(ctx, 0, 38, words) != 38) ++wrong;
  if (modbus_read_registers(ctx, 0, 8, words) != 8) ++wrong;
  if (modbus_read_input_bits(ctx, 0, 7, bits) != 7) ++wrong;
  if (modbus_read_input_registers(ctx, 9000, 10, words) != -1 || errno != EMBXILADD) ++wrong;
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
  const std::uint64_t before = allocations_so_far();
  for (int i = 0; i < kRounds; ++i) wrong += read_round(ctx);
  const std::uint64_t after = allocations_so_far();
  modbus_close(ctx);
  modbus_free(ctx);
  CHECK(wrong == 0);
  INFO("reads: ", kRounds * 5);
  CHECK(after - before == 0);
}

}  // namespace

TEST_CASE("a read allocates nothing once its connection is open, served on a TCP thread") {
  check_reads_allocate_nothing(1);
}

TEST_CASE("a read allocates nothing once its connection is open, served on the buses' thread") {
  check_reads_allocate_nothing(0);
}

TEST_CASE("the counting allocator counts") {
  // Else the two above could pass on a program whose operator new is not the counting one.
  const std::uint64_t before = allocations_so_far();
  auto held = std::make_unique<int>(1);
  CHECK(allocations_so_far() == before + 1);
  CHECK(*held == 1);
}
