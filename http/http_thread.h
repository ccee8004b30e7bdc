// The HTTP server on an event loop and thread of its own, so that nothing it does (TLS, a
// password check's wait, a slow client, a console request waiting for a sensor) ever runs on
// the buses' thread. Made, started and stopped from the buses' thread; the server itself is
// touched only on its own thread after start(). finished() says when the thread has ended, so
// a reload that replaced it may free it (gateway/retired.h).
//
// Nothing here waits for the HTTP thread: stop() returns at once and the thread stops its
// server on its own. A server made to replace it on the same port (a reload) is given its
// port_released() flag and binds the port once that says it is free (start()).
#pragma once

#include <atomic>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <thread>

#include "http/http_server.h"

namespace tiltgate {

class HttpThread {
 public:
  // True once the server's listening socket is closed (or it never had one): shared with the
  // server that replaces it, which may bind the port from then on.
  using PortRelease = std::shared_ptr<const std::atomic<bool>>;
  // What became of the binding, and the port bound (0 when it failed). Called once: on the
  // calling thread of start(), or on the HTTP thread when the port was still held.
  using Started = std::function<void(const Expected<Done, std::string>& bound,
                                     std::uint16_t port)>;

  // While a replaced server still holds the port, binding is tried again this often, for at
  // most this long (a server stuck on its thread: its port is given up on).
  static constexpr std::chrono::milliseconds kRebindPause{10};
  static constexpr std::chrono::milliseconds kRebindPatience{5000};

  HttpThread(HttpHandler handler, HttpServerOptions options);
  ~HttpThread();
  HttpThread(const HttpThread&) = delete;
  HttpThread& operator=(const HttpThread&) = delete;

  // Binds the port on the calling thread, so an error is reported at once, then runs the
  // server on the thread. `replaced`: the port_released() of the server this one replaces; a
  // bind that fails while it still holds the port is tried again on the HTTP thread instead,
  // until it lets the port go. A bind that fails then, or a failure of anything else, fails.
  void start(Started report, PortRelease replaced = {});
  std::uint16_t local_port() const { return port_; }  // 0 until bound
  // Returns at once: the server stops accepting and closes its connections on its own thread
  // (port_released() then says its port is free); the thread ends once they are gone.
  void stop();
  PortRelease port_released() const { return released_; }
  bool finished() const { return !running_.load(); }
  HttpServerStats stats() const { return server_->stats(); }  // any thread
  // The executor the server runs on: the handler's work is there.
  boost::asio::any_io_executor executor() { return io_.get_executor(); }

 private:
  // The server listens on port_ from now on.
  void bound();
  // On the HTTP thread: binds once `replaced` lets the port go.
  boost::asio::awaitable<void> bind_when_released(PortRelease replaced, Started report);

  boost::asio::io_context io_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint16_t> port_{0};
  std::shared_ptr<std::atomic<bool>> released_ = std::make_shared<std::atomic<bool>>(true);
};

}  // namespace tiltgate
