// [http] max_requests_per_s and max_client_requests_per_s on the HTTP server: requests beyond
// them wait for their turn and are all answered, in order, on the same kept-alive connection;
// nothing is refused or closed. Counts only, never times.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <functional>
#include <future>
#include <string>
#include <thread>

#include "sim/support/modbus_test_server.h"
#include "http/http_routes.h"
#include "http/http_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// `count` GETs of /healthz in one send, kept alive: answered one after another.
Bytes pipelined_gets(int count) {
  std::string all;
  for (int i = 0; i < count; ++i) all += "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  return Bytes(all.begin(), all.end());
}

// Reads until `count` status lines of 200 have come, or the peer stops sending (5 s).
int answers_ok(RawSocket& socket, int count) {
  std::string seen;
  int found = 0;
  while (found < count) {
    const Bytes more = socket.receive(1);
    if (more.empty()) break;
    seen.push_back(char(more[0]));
    if (seen.size() >= 12 && seen.compare(seen.size() - 12, 12, "HTTP/1.1 200") == 0) ++found;
  }
  return found;
}

// A status-only server with `options` on its own thread, `clients` run against its port, then
// the server's counts.
HttpServerStats serve_while(HttpServerOptions options,
                            const std::function<void(std::uint16_t port)>& clients) {
  boost::asio::io_context io;
  options.port = 0;
  const HttpHandler status_only = [](HttpRequest request) -> boost::asio::awaitable<HttpReply> {
    co_return route_http(request.method, request.target, [] { return GatewayStatus{}; });
  };
  HttpServer server(io.get_executor(), status_only, options);
  REQUIRE(server.start().has_value());
  std::thread thread([&] { io.run(); });
  clients(server.local_port());
  std::promise<HttpServerStats> stats;
  boost::asio::post(io, [&] {
    stats.set_value(server.stats());
    server.stop();
  });
  const HttpServerStats seen = stats.get_future().get();
  thread.join();
  return seen;
}

HttpServerStats run_against(HttpServerOptions options, int requests, int& answered) {
  return serve_while(std::move(options), [&](std::uint16_t port) {
    RawSocket client(port);
    client.send(pipelined_gets(requests));
    answered = answers_ok(client, requests);
  });
}

}  // namespace

TEST_CASE("HTTP: a client beyond max_client_requests_per_s waits for its turns, all answered") {
  HttpServerOptions options;
  options.max_client_requests_per_s = 50;  // 4 at once, then one every 20 ms
  int answered = 0;
  const HttpServerStats stats = run_against(options, 8, answered);
  CHECK(answered == 8);
  CHECK(stats.requests == 8);
  CHECK(stats.requests_delayed >= 3);
  CHECK(stats.requests_delayed <= 4);
  CHECK(stats.delay_seconds > 0);
  CHECK(stats.closed.timed_out == 0);
}

TEST_CASE("HTTP: max_requests_per_s holds the clients together, and without rates nothing waits") {
  HttpServerOptions options;
  options.max_requests_per_s = 50;
  int answered = 0;
  HttpServerStats stats = run_against(options, 6, answered);
  CHECK(answered == 6);
  CHECK(stats.requests_delayed >= 1);
  stats = run_against(HttpServerOptions{}, 20, answered);
  CHECK(answered == 20);
  CHECK(stats.requests_delayed == 0);
}

TEST_CASE("HTTP: a connection that sends nothing (a browser's preconnect) is closed, not counted") {
  HttpServerOptions options;
  options.request_timeout = std::chrono::milliseconds(200);
  const HttpServerStats seen = serve_while(options, [](std::uint16_t port) {
    RawSocket preconnect(port);
    CHECK(preconnect.closed_by_server());
    const std::string half = "GET /hea";
    RawSocket slow(port);
    slow.send(Bytes(half.begin(), half.end()));
    CHECK(slow.closed_by_server());
  });
  CHECK(seen.closed.timed_out == 1);  // the half request only
}
