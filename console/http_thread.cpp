#include "console/http_thread.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include <future>

namespace tiltgate {

namespace asio = boost::asio;

HttpThread::HttpThread(HttpHandler handler, HttpServerOptions options)
    : server_(std::make_unique<HttpServer>(io_.get_executor(), std::move(handler),
                                           std::move(options))) {}

HttpThread::~HttpThread() {
  // Whatever is still suspended (a request waiting for the buses' loop, which has stopped) is
  // dropped with the loop: the thread ends now, then the server, then the loop.
  io_.stop();
  if (thread_.joinable()) thread_.join();
  server_.reset();
}

Expected<Done, std::string> HttpThread::start() {
  if (auto started = server_->start(); !started) return started;
  port_ = server_->local_port();
  running_ = true;
  thread_ = std::thread([this] {
    try {
      io_.run();
    } catch (const std::exception& error) {
      spdlog::error("HTTP server stopped: {}", error.what());
    }
    running_ = false;
  });
  return Done{};
}

void HttpThread::stop() {
  if (stopping_.exchange(true) || !running_) return;
  // Waited for: once this returns the port is free, so the server a reload makes next can bind
  // it (the HTTP thread is never busy for long; should it be stuck, the wait gives up).
  auto stopped = std::make_shared<std::promise<void>>();
  std::future<void> done = stopped->get_future();
  asio::post(io_, [this, stopped] {
    server_->stop();
    stopped->set_value();
  });
  done.wait_for(std::chrono::seconds(2));
}

}  // namespace tiltgate
