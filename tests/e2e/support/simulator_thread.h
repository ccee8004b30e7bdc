// A bus simulator running on its own thread, for tests that drive the real gateway binary and
// still want to inspect or fault the simulated modules. Every access goes through call(),
// which runs on the simulator's thread. Written for any simulator with the Rieker and Dyna
// simulators' shape (constructed from an io_context and options; start(), stop()).
#pragma once

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <future>
#include <stdexcept>
#include <thread>

#include "modbus_rtu/simulator/simulator.h"
#include "rieker/simulator.h"
#include "spectron/simulator.h"

namespace tiltgate::test {

template <class Simulator>
class BusSimulatorThread {
 public:
  template <class Options>
  explicit BusSimulatorThread(Options options)
      : work_(io_.get_executor()), simulator_(io_, std::move(options)) {
    auto started = simulator_.start();
    if (!started) throw std::runtime_error(started.error());
    thread_ = std::thread([this] { io_.run(); });
  }
  BusSimulatorThread(const BusSimulatorThread&) = delete;
  BusSimulatorThread& operator=(const BusSimulatorThread&) = delete;

  template <class F>
  auto call(F f) {
    std::packaged_task<decltype(f(simulator_))()> task([&] { return f(simulator_); });
    auto result = task.get_future();
    boost::asio::post(io_, [&task] { task(); });
    return result.get();
  }

  ~BusSimulatorThread() {
    call([](Simulator& sim) { sim.stop(); });
    work_.reset();
    io_.stop();
    thread_.join();
  }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  Simulator simulator_;
  std::thread thread_;
};

using SimulatorThread = BusSimulatorThread<rieker::RiekerSimulator>;
using DynaSimulatorThread = BusSimulatorThread<spectron::DynaSimulator>;
using RtuSimulatorThread = BusSimulatorThread<modbus_rtu::RtuSimulator>;

}  // namespace tiltgate::test
