#include "modbus_tcp/tcp_worker_pool.h"

#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include <cerrno>
#include <exception>

namespace tiltgate {

namespace {

// How much nicer than the rest of the gateway the Modbus TCP threads run. Under a flood of
// requests they would take every core they can, and a bus's thread that has to wait for one
// after each reply leaves the wire idle: with the threads at +5 a 64-client flood costs the
// bus about 2 % of its polls instead of 6 % (docs/performance.md, "The bus as the gateway runs
// it"). Relative, so a service started at another nice keeps the difference.
constexpr int kTcpThreadNiceness = 5;

void run_nicer_than_the_buses() {
  const pid_t thread = pid_t(::syscall(SYS_gettid));
  errno = 0;
  const int nice = ::getpriority(PRIO_PROCESS, id_t(thread));
  if (errno == 0) ::setpriority(PRIO_PROCESS, id_t(thread), nice + kTcpThreadNiceness);
}

}  // namespace

std::size_t default_tcp_threads() {
  const unsigned cores = std::thread::hardware_concurrency();
  return cores == 0 ? 1 : cores;
}

TcpWorkerPool::TcpWorkerPool(std::size_t threads) {
  if (threads == 0) threads = 1;
  for (std::size_t i = 0; i < threads; ++i) {
    auto worker = std::make_unique<Worker>();
    ConnectionLoop& loop = worker->loop;
    worker->thread = std::thread([&loop, i] {
      // OpenSSL writes a TLS connection's socket with write(): a client gone away must cost
      // an EPIPE there, not the process. Plain sockets are sent to with MSG_NOSIGNAL.
      sigset_t pipe;
      sigemptyset(&pipe);
      sigaddset(&pipe, SIGPIPE);
      pthread_sigmask(SIG_BLOCK, &pipe, nullptr);
      run_nicer_than_the_buses();
      // A connection that throws is a bug; it costs that turn of the loop, not the thread.
      for (;;) {
        try {
          loop.run();
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

ConnectionLoop& TcpWorkerPool::next() {
  const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed) % workers_.size();
  return workers_[i]->loop;
}

void TcpWorkerPool::stop(std::chrono::milliseconds grace) {
  if (stopped_) return;
  stopped_ = true;
  for (auto& worker : workers_) worker->loop.stop();
  // run() returns by itself once a thread's connections have all ended.
  const auto deadline = std::chrono::steady_clock::now() + grace;
  for (auto& worker : workers_)
    while (!worker->loop.stopped() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  for (auto& worker : workers_) {
    if (!worker->loop.stopped())
      spdlog::warn("Modbus TCP thread still busy {} ms after stop: stopped", grace.count());
    worker->loop.stop(true);
    if (worker->thread.joinable()) worker->thread.join();
  }
}

}  // namespace tiltgate
