// The gateway's threads as `tiltgate run` has them, around a fake bus (fake_bus.h): the
// sensors a test adds, the router, a Modbus TCP server on loopback served on `tcp_threads`
// worker threads (0: on the one thread of the server's own), and the buses' io_context on a
// thread of its own. A test adds and routes its sensors, then calls serve().
#pragma once

#include <doctest/doctest.h>

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
#include <vector>

#include "line_scheduling/bus_scheduler.h"
#include "gateway/request_router.h"
#include "modbus_tcp/modbus_tcp_server.h"
#include "modbus_tcp/tcp_worker_pool.h"
#include "unit/support/fake_bus.h"

namespace tiltgate::test {

struct ServedPlant {
  ServedPlant(std::size_t tcp_threads, bool writes)
      : workers(tcp_threads > 0 ? std::make_unique<TcpWorkerPool>(tcp_threads) : nullptr),
        router(io.get_executor(), RouterOptions{writes, WordOrder::big, std::chrono::seconds(3)}) {}

  // Starts the server, the bus and the bus's thread, then waits until each sensor has a
  // reading: before it, reads are rightly answered 0x0B.
  void serve() {
    ModbusServerOptions options;
    options.listen = "127.0.0.1";
    options.port = 0;
    server = std::make_unique<ModbusTcpServer>(io.get_executor(), router, options, workers.get());
    REQUIRE(server->start().has_value());
    port = server->local_port();
    boost::asio::co_spawn(io, scheduler.run(), boost::asio::detached);
    bus_thread = std::thread([this] { io.run(); });
    for (const auto& sensor : sensors)
      while (!sensor->snapshot() || !sensor->snapshot()->state.reading)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }

  // Runs `task` on the bus's thread, after whatever that thread is doing, and returns once
  // it has run.
  template <class Task>
  void run_on_bus_thread(Task task) {
    std::promise<void> done;
    boost::asio::post(io, [&] {
      task();
      done.set_value();
    });
    done.get_future().wait();
  }

  // Returns once the bus's thread has finished what it was doing: it also accepts the
  // server's clients, and a connection is served before its accept's turn has ended.
  void wait_for_bus_thread() {
    run_on_bus_thread([] {});
  }

  ~ServedPlant() {
    const auto stop = [this] {
      router.stop();
      if (server) server->stop();
      scheduler.stop();
    };
    if (bus_thread.joinable()) {
      run_on_bus_thread(stop);
    } else {
      stop();  // serve() never ran or failed: nothing runs on io
    }
    if (workers) workers->stop();
    guard.reset();
    io.stop();
    if (bus_thread.joinable()) bus_thread.join();
  }

  // Declared first, destroyed last: the connections the server holds refer to its loops.
  std::unique_ptr<TcpWorkerPool> workers;
  boost::asio::io_context io;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> guard{
      io.get_executor()};
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  RequestRouter router;
  BusEvents events;
  std::vector<std::shared_ptr<GatewaySensor>> sensors;
  std::unique_ptr<ModbusTcpServer> server;
  std::uint16_t port = 0;
  std::thread bus_thread;
};

}  // namespace tiltgate::test
