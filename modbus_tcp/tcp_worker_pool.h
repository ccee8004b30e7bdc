// The threads that serve Modbus TCP connections ([server] threads): one io_context and one
// thread each, so each connection's socket, timers and coroutines live on one thread and need
// no strand. The buses stay on the main event loop, which no TCP work reaches but writes and
// forwarded requests (gateway/request_router.h).
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <thread>
#include <vector>

namespace tiltgate {

class TcpWorkerPool {
 public:
  // Starts `threads` threads (at least one).
  explicit TcpWorkerPool(std::size_t threads);
  // stop(), if it was not called.
  ~TcpWorkerPool();
  TcpWorkerPool(const TcpWorkerPool&) = delete;
  TcpWorkerPool& operator=(const TcpWorkerPool&) = delete;

  // The next thread's executor, round robin: where the next connection is served.
  boost::asio::any_io_executor next();
  std::size_t size() const { return workers_.size(); }

  // Lets each thread end once its connections have ended (their sockets closed by the
  // servers' stop()), waiting up to `grace`; what is still running then is stopped, and the
  // threads are joined.
  void stop(std::chrono::milliseconds grace = std::chrono::seconds(2));

 private:
  struct Worker {
    boost::asio::io_context io{1};  // one thread: the concurrency hint lets asio skip locks
    boost::asio::executor_work_guard<boost::asio::io_context::executor_type> guard{
        io.get_executor()};
    std::thread thread;
  };

  std::vector<std::unique_ptr<Worker>> workers_;
  std::atomic<std::size_t> next_ = 0;
  bool stopped_ = false;
};

// [server] threads when not given: one per core.
std::size_t default_tcp_threads();

}  // namespace tiltgate
