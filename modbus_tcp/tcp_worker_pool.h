// The threads that serve Modbus TCP connections ([server] threads): one ConnectionLoop and one
// thread each, so each connection's socket, buffers and deadlines live on one thread and need
// no lock. The buses stay on the main event loop, which no TCP work reaches but writes and
// forwarded requests (gateway/request_router.h). What the threads answer together is held to
// one request rate ([server] max_requests_per_s, doors/request_rate.h): every server
// served on the pool takes its requests' turns from it.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <thread>
#include <vector>

#include "modbus_tcp/connection_loop.h"
#include "doors/request_rate.h"

namespace tiltgate {

class TcpWorkerPool {
 public:
  // Starts `threads` threads (at least one).
  explicit TcpWorkerPool(std::size_t threads);
  // stop(), if it was not called.
  ~TcpWorkerPool();
  TcpWorkerPool(const TcpWorkerPool&) = delete;
  TcpWorkerPool& operator=(const TcpWorkerPool&) = delete;

  // The next thread's loop, round robin: where the next connection is served.
  ConnectionLoop& next();
  std::size_t size() const { return workers_.size(); }
  // Every connection's requests together, on every thread (the servers set its rate).
  SharedRateLimit& total_rate() { return total_rate_; }

  // Lets each thread end once its connections have ended (their sockets closed by the
  // servers' stop()), waiting up to `grace`; what is still running then is stopped, and the
  // threads are joined.
  void stop(std::chrono::milliseconds grace = std::chrono::seconds(2));

 private:
  struct Worker {
    ConnectionLoop loop;
    std::thread thread;
  };

  SharedRateLimit total_rate_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::atomic<std::size_t> next_ = 0;
  bool stopped_ = false;
};

// [server] threads when not given: one per core.
std::size_t default_tcp_threads();

}  // namespace tiltgate
