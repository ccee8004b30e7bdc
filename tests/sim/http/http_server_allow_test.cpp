// [http] allow on the status API's server: a host outside it is closed at accept and counted,
// an allowed one is answered. 127.0.0.2 is another host (loopback has all of 127.0.0.0/8).
#include <doctest/doctest.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <future>
#include <string>
#include <thread>

#include "http/http_routes.h"
#include "http/http_server.h"
#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("HTTP: a host outside [http] allow is closed at accept, an allowed one is answered") {
  boost::asio::io_context io;
  HttpServerOptions options;
  options.port = 0;
  const std::vector<std::string> entries{"127.0.0.1"};
  auto allow = AddressAllowList::parse(entries);
  REQUIRE(allow.has_value());
  options.allow = *allow;
  const HttpHandler status_only = [](HttpRequest request) -> boost::asio::awaitable<HttpReply> {
    co_return route_http(request.method, request.target, [] { return GatewayStatus{}; });
  };
  HttpServer server(io.get_executor(), status_only, options);
  REQUIRE(server.start().has_value());
  std::thread thread([&] { io.run(); });

  RawSocket stranger(server.local_port(), "127.0.0.2");
  CHECK(stranger.closed_by_server());
  RawSocket local(server.local_port(), "127.0.0.1");
  const std::string request = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  local.send(Bytes(request.begin(), request.end()));
  const Bytes reply = local.receive(12);
  CHECK(std::string(reply.begin(), reply.end()) == "HTTP/1.1 200");

  std::promise<HttpServerStats> stats;
  boost::asio::post(io, [&] {
    stats.set_value(server.stats());
    server.stop();
  });
  const HttpServerStats seen = stats.get_future().get();
  CHECK(seen.denied == 1);
  CHECK(seen.accepted == 1);
  thread.join();
}
