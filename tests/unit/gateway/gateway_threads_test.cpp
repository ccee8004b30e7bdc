// The gateway's threads together: the bus polls on its event loop while Modbus TCP clients are
// served on a pool of threads (modbus_tcp/tcp_worker_pool.h), read sensors from their snapshots,
// write through the bus's executor, and the routes are replaced meanwhile. Run under
// ThreadSanitizer by scripts/sanitize --threads; here it checks what a client sees: every
// reply whole and from one reading, none lost, no unit missing while routes are replaced.
#include <doctest/doctest.h>
#include <modbus.h>

#include <atomic>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <future>
#include <memory>
#include <thread>
#include <vector>

#include "line_scheduling/bus_scheduler.h"
#include "gateway/gateway_aggregate.h"
#include "modbus_tcp/modbus_tcp_server.h"
#include "gateway/request_router.h"
#include "modbus_tcp/tcp_worker_pool.h"
#include "unit/support/fake_bus.h"
#include "unit/support/served_plant.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

constexpr int kSensors = 3;
constexpr std::uint8_t kAggregateUnit = 200;

// Three counting sensors polled every millisecond on a fake bus, the router and a server with
// two TCP threads; the bus's io_context runs on a thread of its own, as in `tiltgate run`.
struct ThreadedPlant : ServedPlant {
  ThreadedPlant() : ServedPlant(2, true) {
    for (int i = 1; i <= kSensors; ++i) {
      auto sensor = fake_sensor("s" + std::to_string(i), std::uint8_t(i), std::uint32_t(i),
                                events, 1ms);
      fake_driver(*sensor).counting = true;
      sensors.push_back(std::shared_ptr<GatewaySensor>(std::move(sensor)));
      scheduler.add(sensors.back());
    }
    route();
    serve();
  }

  // The sensors and an aggregate of their angles on unit 200, all routed in one update, as a
  // reload does. On the bus's thread once it runs.
  void route() {
    router.begin_update();
    router.clear();
    for (const auto& sensor : sensors) router.add(sensor);
    AggregateConfig config;
    config.unit_id = kAggregateUnit;
    config.points = {"angle_x", "angle_y"};
    config.sensors = {"s1", "s2", "s3"};
    auto aggregate = make_gateway_aggregate(config, sensors);
    REQUIRE(aggregate.has_value());
    router.add(*aggregate);
    router.commit_update();
  }
};

struct ClientTally {
  int replies = 0;
  int failures = 0;  // no reply, or an exception
  int torn = 0;      // x and y of one sensor from different readings
};

// `reads` requests on one connection: a sensor's angles (FC4 0..3) or, every third one, the
// aggregate's twelve registers; x and y of each sensor must be equal (one reading).
ClientTally read_many(std::uint16_t port, int client, int reads) {
  ClientTally tally;
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  REQUIRE(ctx != nullptr);
  if (modbus_connect(ctx) != 0) {
    modbus_free(ctx);
    tally.failures = reads;
    return tally;
  }
  for (int i = 0; i < reads; ++i) {
    const bool aggregate = i % 3 == 2;
    const int unit = aggregate ? kAggregateUnit : 1 + (client + i) % kSensors;
    const int count = aggregate ? 4 * kSensors : 4;
    std::uint16_t regs[4 * kSensors] = {};
    modbus_set_slave(ctx, unit);
    if (modbus_read_input_registers(ctx, 0, count, regs) != count) {
      MESSAGE("unit ", unit, ": ", std::string(modbus_strerror(errno)));  // why, if it fails
      ++tally.failures;
      continue;
    }
    ++tally.replies;
    for (int block = 0; block < count; block += 4)
      if (regs[block] != regs[block + 2] || regs[block + 1] != regs[block + 3]) ++tally.torn;
  }
  modbus_close(ctx);
  modbus_free(ctx);
  return tally;
}

}  // namespace

TEST_CASE("threads: clients on two TCP threads read whole readings while the bus polls and "
          "the routes are replaced") {
  ThreadedPlant plant;
  std::atomic<bool> reading{true};
  // The routes replaced over and over meanwhile, on the bus's thread, as reloads would.
  std::thread reloader([&] {
    while (reading) {
      std::promise<void> routed;
      asio::post(plant.io, [&] {
        plant.route();
        routed.set_value();
      });
      routed.get_future().wait();
      std::this_thread::sleep_for(1ms);
    }
  });
  // And a writer: each write goes to the bus's thread and comes back with its outcome.
  std::atomic<int> writes_ok{0};
  std::thread writer([&] {
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", plant.port);
    REQUIRE(ctx != nullptr);
    if (modbus_connect(ctx) == 0) {
      modbus_set_slave(ctx, 1);
      for (int i = 0; i < 50; ++i)
        if (modbus_write_register(ctx, 0, std::uint16_t(1 + i % 3)) == 1) ++writes_ok;
      modbus_close(ctx);
    }
    modbus_free(ctx);
  });

  constexpr int kClients = 6;
  constexpr int kReads = 300;
  std::vector<std::future<ClientTally>> clients;
  for (int c = 0; c < kClients; ++c)
    clients.push_back(std::async(std::launch::async, read_many, plant.port, c, kReads));
  ClientTally total;
  for (auto& client : clients) {
    const ClientTally tally = client.get();
    total.replies += tally.replies;
    total.failures += tally.failures;
    total.torn += tally.torn;
  }
  writer.join();
  reading = false;
  reloader.join();

  CHECK(total.replies == kClients * kReads);
  CHECK(total.failures == 0);
  CHECK(total.torn == 0);
  CHECK(writes_ok == 50);
  // The bus went on polling throughout (its counting reading moved on).
  CHECK(plant.sensors[0]->snapshot()->state.reading->angle_x > 10);
  const ModbusServerStats stats = plant.server->stats();
  CHECK(stats.accepted == kClients + 1);
  CHECK(stats.requests == std::uint64_t(kClients * kReads + 50));
}

TEST_CASE("threads: the worker pool ends its threads once their connections are closed") {
  TcpWorkerPool pool(3);
  CHECK(pool.size() == 3);
  std::atomic<int> ran{0};
  for (int i = 0; i < 9; ++i) pool.next().post([&] { ++ran; });
  pool.stop(10s);  // returns as soon as the threads ran out of work
  CHECK(ran == 9);
  pool.stop();  // again: nothing happens
}
