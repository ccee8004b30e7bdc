#include "http/http_thread.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

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
  released_->store(true);
}

void HttpThread::bound() {
  port_ = server_->local_port();
  released_->store(false);
}

void HttpThread::start(Started report, PortRelease replaced) {
  // Looked at before the bind: a port let go after a failed bind is still tried again.
  const bool port_held = replaced && !replaced->load();
  auto started = server_->start();
  if (!started && !port_held) {
    report(started, 0);
    return;
  }
  if (started) {
    bound();
    report(started, port_);
  } else {
    asio::co_spawn(io_, bind_when_released(std::move(replaced), std::move(report)),
                   asio::detached);
  }
  running_ = true;
  thread_ = std::thread([this] {
    try {
      io_.run();
    } catch (const std::exception& error) {
      spdlog::error("HTTP server stopped: {}", error.what());
      server_->stop();  // the port goes with it
    }
    released_->store(true);
    running_ = false;
  });
}

asio::awaitable<void> HttpThread::bind_when_released(PortRelease replaced, Started report) {
  const auto give_up = std::chrono::steady_clock::now() + kRebindPatience;
  asio::steady_timer pause(io_);
  for (;;) {
    if (stopping_) co_return;
    const bool port_held = !replaced->load() && std::chrono::steady_clock::now() < give_up;
    auto started = server_->start();
    if (started) bound();
    if (started || !port_held) {
      report(started, port_);
      co_return;
    }
    pause.expires_after(kRebindPause);
    boost::system::error_code ec;
    co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

void HttpThread::stop() {
  if (stopping_.exchange(true) || !running_) return;
  // Not waited for: the buses' thread goes on at once. The server a reload makes next binds
  // the port once this one has let it go (port_released()).
  asio::post(io_, [this] {
    server_->stop();
    released_->store(true);
  });
}

}  // namespace tiltgate
