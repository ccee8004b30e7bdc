// The HTTP server on an event loop and thread of its own, so that nothing it does (TLS, a
// password check's wait, a slow client, a console request waiting for a sensor) ever runs on
// the buses' thread. Made, started and stopped from the buses' thread; the server itself is
// touched only on its own thread after start(). finished() says when the thread has ended, so
// a reload that replaced it may free it (gateway/retired.h).
#pragma once

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <memory>
#include <thread>

#include "status/http_server.h"

namespace tiltgate {

class HttpThread {
 public:
  HttpThread(HttpHandler handler, HttpServerOptions options);
  ~HttpThread();
  HttpThread(const HttpThread&) = delete;
  HttpThread& operator=(const HttpThread&) = delete;

  // Binds the port (on the calling thread, so an error is reported at once), then runs the
  // server on the thread.
  Expected<Done, std::string> start();
  std::uint16_t local_port() const { return port_; }
  // The server stops accepting (its port is free when this returns) and closes its
  // connections; the thread ends once they are gone.
  void stop();
  bool finished() const { return !running_.load(); }
  HttpServerStats stats() const { return server_->stats(); }  // any thread
  // The executor the server runs on: the handler's work is there.
  boost::asio::any_io_executor executor() { return io_.get_executor(); }

 private:
  boost::asio::io_context io_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stopping_{false};
  std::uint16_t port_ = 0;
};

}  // namespace tiltgate
