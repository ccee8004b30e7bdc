#include "modbus_tcp/tcp_worker_pool.h"

#include <spdlog/spdlog.h>

#include <exception>

namespace tiltgate {

std::size_t default_tcp_threads() {
  const unsigned cores = std::thread::hardware_concurrency();
  return cores == 0 ? 1 : cores;
}

TcpWorkerPool::TcpWorkerPool(std::size_t threads) {
  if (threads == 0) threads = 1;
  for (std::size_t i = 0; i < threads; ++i) {
    auto worker = std::make_unique<Worker>();
    boost::asio::io_context& io = worker->io;
    worker->thread = std::thread([&io, i] {
      // A handler that throws is a bug; it costs the one connection, not the thread.
      for (;;) {
        try {
          io.run();
          return;
        } catch (const std::exception& e) {
          spdlog::error("Modbus TCP thread {}: {}", i, e.what());
        }
      }
    });
    workers_.push_back(std::move(worker));
  }
}

TcpWorkerPool::~TcpWorkerPool() { stop(); }

boost::asio::any_io_executor TcpWorkerPool::next() {
  const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed) % workers_.size();
  return workers_[i]->io.get_executor();
}

void TcpWorkerPool::stop(std::chrono::milliseconds grace) {
  if (stopped_) return;
  stopped_ = true;
  for (auto& worker : workers_) worker->guard.reset();
  // run() returns by itself once a thread's connections have all ended.
  const auto deadline = std::chrono::steady_clock::now() + grace;
  for (auto& worker : workers_)
    while (!worker->io.stopped() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  for (auto& worker : workers_) {
    if (!worker->io.stopped())
      spdlog::warn("Modbus TCP thread still busy {} ms after stop: stopped", grace.count());
    worker->io.stop();
    if (worker->thread.joinable()) worker->thread.join();
  }
}

}  // namespace tiltgate
