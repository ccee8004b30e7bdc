// A Rieker simulator running on its own thread, for tests that drive the real gateway binary
// and still want to inspect or fault the simulated sensors. Every access goes through
// call(), which runs on the simulator's thread.
#pragma once

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <future>
#include <thread>

#include "rieker/simulator.h"

namespace tiltgate::test {

class SimulatorThread {
 public:
  explicit SimulatorThread(rieker::RiekerSimulatorOptions options)
      : work_(io_.get_executor()), simulator_(io_, std::move(options)) {
    auto started = simulator_.start();
    if (!started) throw std::runtime_error(started.error());
    thread_ = std::thread([this] { io_.run(); });
  }
  template <class F>
  auto call(F f) {
    std::packaged_task<decltype(f(simulator_))()> task([&] { return f(simulator_); });
    auto result = task.get_future();
    boost::asio::post(io_, [&task] { task(); });
    return result.get();
  }

  ~SimulatorThread() {
    call([](rieker::RiekerSimulator& sim) { sim.stop(); });
    work_.reset();
    io_.stop();
    thread_.join();
  }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  rieker::RiekerSimulator simulator_;
  std::thread thread_;
};

}  // namespace tiltgate::test
