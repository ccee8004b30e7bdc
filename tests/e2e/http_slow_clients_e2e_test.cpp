// `tiltgate demo`'s HTTP port under clients that never finish a request (docs/operations.md,
// "What the PLC sees when something fails"): sixteen trickling a byte a second and two hundred
// idle ones, each reconnecting as soon as it is closed, while a reader fetches pages from
// 127.0.0.1. All of 127.0.0.0/8 is loopback, so the attackers bind 127.0.0.2 and up: from one
// address the per-address cap keeps them to their share; from many, the reader's connection
// makes room by closing the one that waited longest without a whole request.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/http_client.h"
#include "e2e/support/http_demo.h"

using namespace tiltgate::test;
namespace asio = boost::asio;
using asio::ip::tcp;
using namespace std::chrono_literals;

namespace {

asio::awaitable<void> pause(std::chrono::milliseconds how_long) {
  asio::steady_timer timer(co_await asio::this_coro::executor, how_long);
  boost::system::error_code ec;
  co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ec));
}

// A socket from `from` connected to the gateway's HTTP port; closed when the connect failed.
asio::awaitable<tcp::socket> connect_from(const std::string& from, std::uint16_t port) {
  tcp::socket socket(co_await asio::this_coro::executor);
  boost::system::error_code ec;
  socket.open(tcp::v4(), ec);
  socket.bind({asio::ip::make_address(from), 0}, ec);
  if (!ec)
    co_await socket.async_connect({asio::ip::make_address("127.0.0.1"), port},
                                  asio::redirect_error(asio::use_awaitable, ec));
  if (ec) socket.close(ec);
  co_return socket;
}

// Whether the server has closed `socket` (it never answers these clients, so anything readable
// is the end).
bool closed_by_server(tcp::socket& socket) {
  boost::system::error_code ec;
  socket.non_blocking(true, ec);
  char byte = 0;
  socket.read_some(asio::buffer(&byte, 1), ec);
  return ec != asio::error::would_block;
}

// Sends a request's header a byte a second, never ending it; reconnects when closed.
asio::awaitable<void> trickle(std::string from, std::uint16_t port) {
  const std::string header = "GET /api/sensors HTTP/1.1\r\nHost: localhost\r\nX-Slow: " +
                             std::string(8000, 'a');
  for (;;) {
    tcp::socket socket = co_await connect_from(from, port);
    for (std::size_t sent = 0; socket.is_open() && sent < header.size(); ++sent) {
      boost::system::error_code ec;
      co_await asio::async_write(socket, asio::buffer(&header[sent], 1),
                                 asio::redirect_error(asio::use_awaitable, ec));
      if (ec) break;
      co_await pause(1000ms);
      if (closed_by_server(socket)) break;
    }
    if (!socket.is_open()) co_await pause(50ms);
  }
}

// Connects and sends nothing; reconnects at once when closed.
asio::awaitable<void> stay_idle(std::string from, std::uint16_t port) {
  for (;;) {
    tcp::socket socket = co_await connect_from(from, port);
    if (!socket.is_open()) {
      co_await pause(50ms);
      continue;
    }
    char byte = 0;
    boost::system::error_code ec;
    co_await socket.async_read_some(asio::buffer(&byte, 1),
                                    asio::redirect_error(asio::use_awaitable, ec));
  }
}

// The slow and idle clients, on a thread of their own until destroyed.
class Attackers {
 public:
  Attackers(std::uint16_t port, const std::vector<std::string>& slow_from,
            const std::vector<std::string>& idle_from) {
    for (const std::string& from : slow_from)
      asio::co_spawn(io_, trickle(from, port), asio::detached);
    for (const std::string& from : idle_from)
      asio::co_spawn(io_, stay_idle(from, port), asio::detached);
    thread_ = std::thread([this] { io_.run(); });
  }
  ~Attackers() {
    io_.stop();
    thread_.join();
  }

 private:
  asio::io_context io_;
  std::thread thread_;
};

// `count` addresses from 127.0.0.`first` on, `each` times each.
std::vector<std::string> addresses(int first, int count, int each) {
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < each; ++j) out.push_back(fmt::format("127.0.0.{}", first + i));
  return out;
}

// One GET from 127.0.0.1 on a connection of its own: answered 200 within `limit`.
bool page_answered(std::uint16_t port, std::chrono::seconds limit) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  timeval bound{limit.count(), 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &bound, sizeof bound);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &bound, sizeof bound);  // the connect too
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto start = std::chrono::steady_clock::now();
  bool answered = false;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) {
    const std::string request =
        "GET /api/sensors HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n";
    if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size()))
      answered = read_to_close(fd).starts_with("HTTP/1.1 200");
  }
  ::close(fd);
  return answered && std::chrono::steady_clock::now() - start < limit;
}

// Pages fetched one after another, 100 ms apart, while the attackers run: how many answered.
int pages_answered(std::uint16_t port, int pages) {
  int answered = 0;
  for (int i = 0; i < pages; ++i) {
    if (page_answered(port, 5s)) ++answered;
    std::this_thread::sleep_for(100ms);
  }
  return answered;
}

double metric(const std::string& metrics, const std::string& sample) {
  const std::regex line("(^|\n)" + std::regex_replace(sample, std::regex(R"([{}"])"), R"(\$&)") +
                        " ([0-9.e+]+)\n");
  std::smatch found;
  if (!std::regex_search(metrics, found, line)) return -1;
  return std::stod(found[2]);
}

}  // namespace

TEST_CASE("HTTP: trickling and idle clients from one address leave a page reader served") {
  HttpDemo demo;
  int answered = 0;
  constexpr int pages = 40;
  {
    Attackers attackers(demo.http_port, addresses(2, 1, 16), addresses(2, 1, 200));
    std::this_thread::sleep_for(2s);  // every place they can take, taken
    answered = pages_answered(demo.http_port, pages);
  }
  MESSAGE(answered, " of ", pages, " pages answered");
  CHECK(answered >= pages * 95 / 100);
  // Counted, and logged a few lines per address, then only counted.
  const std::string metrics = get(demo.http_port, "/metrics").body;
  CHECK(metric(metrics, "tiltgate_http_clients_closed_total{reason=\"replaced\"}") > 0);
  const std::string log = demo.process.log();
  std::size_t lines = 0;
  for (std::size_t at = 0; (at = log.find("closing HTTP client 127.0.0.2:", at)) != std::string::npos; ++at)
    ++lines;
  CHECK(lines >= 1);
  CHECK(lines <= 5);
}

TEST_CASE("HTTP: trickling and idle clients from forty addresses leave a page reader served") {
  HttpDemo demo;
  int answered = 0;
  constexpr int pages = 40;
  {
    Attackers attackers(demo.http_port, addresses(2, 16, 1), addresses(18, 40, 5));
    std::this_thread::sleep_for(2s);
    answered = pages_answered(demo.http_port, pages);
  }
  MESSAGE(answered, " of ", pages, " pages answered");
  CHECK(answered >= pages * 95 / 100);
  CHECK(get(demo.http_port, "/healthz").status == 200);  // and nothing needs a restart
}

TEST_CASE("HTTP: a client trickling its request a byte every half second is closed 5 s after it connected") {
  HttpDemo demo;
  const int fd = connect_to(demo.http_port, 30);
  const auto start = std::chrono::steady_clock::now();
  const std::string header = "GET /api/sensors HTTP/1.1\r\nHost: localhost\r\nX-Slow: " +
                             std::string(100, 'a');
  bool closed = false;
  for (const char byte : header) {
    if (::send(fd, &byte, 1, MSG_NOSIGNAL) != 1) {
      closed = true;
      break;
    }
    std::this_thread::sleep_for(500ms);
    if (std::chrono::steady_clock::now() - start > 12s) break;
  }
  if (!closed) closed = read_to_close(fd).empty();
  const auto held = std::chrono::steady_clock::now() - start;
  ::close(fd);
  CHECK(closed);
  // 5 s, and one more byte's pause to notice; bytes coming in never extended it.
  CHECK(held >= 4500ms);
  CHECK(held < 8s);
  const std::string metrics = get(demo.http_port, "/metrics").body;
  CHECK(metric(metrics, "tiltgate_http_clients_closed_total{reason=\"timeout\"}") == 1);
}
