// The HTTP server's thread (http/http_thread.h) as a reload replaces it: stop() returns at
// once even while the old server's thread is busy, and the new server on the same port binds
// it once the old one has let it go, then serves there. A port some other socket holds is an
// error at once.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <atomic>
#include <chrono>
#include <future>
#include <optional>
#include <string>
#include <thread>

#include "http/http_thread.h"

using namespace tiltgate;
using namespace std::chrono_literals;
namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

// Answers every request with `body`; the first request to /slow holds its thread `hold` long.
HttpHandler answering(std::string body, std::atomic<bool>* in_slow = nullptr,
                      std::chrono::milliseconds hold = 0ms) {
  return [body, in_slow, hold](HttpRequest request) -> asio::awaitable<HttpReply> {
    if (request.target == "/slow" && in_slow != nullptr) {
      *in_slow = true;
      std::this_thread::sleep_for(hold);  // a handler that keeps its thread busy
    }
    co_return HttpReply{200, "text/plain", body};
  };
}

HttpServerOptions on_port(std::uint16_t port) {
  HttpServerOptions options;
  options.port = port;
  return options;
}

// GET `target` on 127.0.0.1:`port`: the response's body, or nothing when no server is there.
std::optional<std::string> get_body(std::uint16_t port, const std::string& target = "/") {
  asio::io_context io;
  tcp::socket socket(io);
  boost::system::error_code ec;
  socket.connect({asio::ip::make_address("127.0.0.1"), port}, ec);
  if (ec) return std::nullopt;
  const std::string request =
      "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  asio::write(socket, asio::buffer(request), ec);
  std::string response;
  asio::read(socket, asio::dynamic_buffer(response), ec);  // to the end: Connection: close
  const auto body = response.find("\r\n\r\n");
  if (body == std::string::npos) return std::nullopt;
  return response.substr(body + 4);
}

struct Report {
  std::promise<std::pair<bool, std::uint16_t>> promise;
  HttpThread::Started callback() {
    return [this](const Expected<Done, std::string>& bound, std::uint16_t port) {
      promise.set_value({bound.has_value(), port});
    };
  }
};

}  // namespace

TEST_CASE("a reload's HTTP server takes over the port of the one it replaces, and stopping that one does not wait for its thread") {
  std::atomic<bool> in_slow{false};
  HttpThread old_server(answering("old", &in_slow, 400ms), on_port(0));
  Report old_report;
  old_server.start(old_report.callback());
  const auto [old_bound, port] = old_report.promise.get_future().get();
  REQUIRE(old_bound);
  REQUIRE(port != 0);
  CHECK(get_body(port) == "old");

  // The old server's thread is busy with a slow request when the reload stops it.
  auto slow = std::async(std::launch::async, [port = port] { return get_body(port, "/slow"); });
  while (!in_slow) std::this_thread::sleep_for(1ms);
  const auto before = std::chrono::steady_clock::now();
  old_server.stop();
  CHECK(std::chrono::steady_clock::now() - before < 100ms);  // not the 400 ms its thread is busy
  CHECK_FALSE(old_server.port_released()->load());  // its thread has not got to it yet

  HttpThread new_server(answering("new"), on_port(port));
  Report new_report;
  new_server.start(new_report.callback(), old_server.port_released());
  const auto [new_bound, new_port] = new_report.promise.get_future().get();
  CHECK(new_bound);
  CHECK(new_port == port);
  CHECK(old_server.port_released()->load());
  CHECK(get_body(port) == "new");
  slow.wait();
}

TEST_CASE("an HTTP port held by another socket is an error at once, replaced server or not") {
  asio::io_context io;
  tcp::acceptor holder(io, {asio::ip::make_address("127.0.0.1"), 0});
  const std::uint16_t port = holder.local_endpoint().port();

  HttpThread server(answering("x"), on_port(port));
  std::optional<bool> bound;
  server.start([&](const Expected<Done, std::string>& started, std::uint16_t) {
    bound = started.has_value();
  });
  REQUIRE(bound.has_value());  // said on this thread, before start() returned
  CHECK_FALSE(*bound);

  // The server it replaces let its port go already: the holder is somebody else.
  HttpThread replacing(answering("y"), on_port(port));
  auto released = std::make_shared<std::atomic<bool>>(true);
  std::optional<bool> replacing_bound;
  replacing.start(
      [&](const Expected<Done, std::string>& started, std::uint16_t) {
        replacing_bound = started.has_value();
      },
      released);
  REQUIRE(replacing_bound.has_value());
  CHECK_FALSE(*replacing_bound);
  CHECK(replacing.finished());
}
