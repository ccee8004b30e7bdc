// A SerialLine on a device server's port (device_server/network_port.h) against a small
// scripted server on loopback, in raw and in RFC 2217 mode (ser2net's own behaviour is the
// e2e tests'): the bytes, the Telnet escaping, the settings confirmed, a lost connection.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "device_server/serial_line_maker.h"
#include "device_server/telnet_codec.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using tiltgate::LineError;
using tiltgate::LineRequest;
using tiltgate::SerialLine;
using tiltgate::SerialLineOptions;
using tiltgate::test::line_bench::Bytes;
using tiltgate::test::line_bench::CountFramer;
using tiltgate::test::line_bench::Result;
namespace telnet = tiltgate::telnet;

namespace {

// A device server with one "sensor" behind it that answers each request of N bytes with the
// same bytes, each plus one. In RFC 2217 mode it speaks as ser2net does: its own offers on
// accept, answers to the COM-PORT-OPTION's requests, 0xFF doubled both ways.
class ScriptedServer {
 public:
  ScriptedServer(asio::io_context& io, bool telnet_mode)
      : acceptor_(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
        telnet_(telnet_mode) {
    asio::co_spawn(io, serve(), asio::detached);
  }
  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }
  std::string url() const {
    return std::string(telnet_ ? "rfc2217" : "tcp") + "://127.0.0.1:" + std::to_string(port());
  }
  // Closes the connection being served (a server restarted, a reset).
  void drop() {
    boost::system::error_code ignored;
    if (peer_) peer_->close(ignored);
  }

  std::optional<std::uint32_t> baud_set;  // SET-BAUDRATE's value
  std::uint32_t baud_answered = 0;        // 0: answer what was asked
  Bytes raw_received;                     // every byte as it came, Telnet and all
  int connections = 0;

 private:
  asio::awaitable<void> serve() {
    for (;;) {
      boost::system::error_code ec;
      auto socket = std::make_shared<asio::ip::tcp::socket>(acceptor_.get_executor());
      co_await acceptor_.async_accept(*socket, asio::redirect_error(asio::use_awaitable, ec));
      if (ec) co_return;
      ++connections;
      peer_ = socket;
      co_await session(socket);
    }
  }

  asio::awaitable<void> session(std::shared_ptr<asio::ip::tcp::socket> socket) {
    boost::system::error_code ec;
    if (telnet_) {
      Bytes offers{0xFF, 0xFB, 0x03, 0xFF, 0xFD, 0x03, 0xFF, 0xFB, 0x01, 0xFF, 0xFE, 0x01,
                   0xFF, 0xFD, 0x00, 0xFF, 0xFB, 0x00, 0xFF, 0xFD, 0x2C};
      co_await asio::async_write(*socket, asio::buffer(offers),
                                 asio::redirect_error(asio::use_awaitable, ec));
    }
    telnet::Reader reader;
    std::vector<telnet::Command> commands;
    std::array<std::uint8_t, 512> buffer{};
    for (;;) {
      const std::size_t n = co_await socket->async_read_some(
          asio::buffer(buffer), asio::redirect_error(asio::use_awaitable, ec));
      if (ec) co_return;
      raw_received.insert(raw_received.end(), buffer.begin(), buffer.begin() + std::ptrdiff_t(n));
      std::span<std::uint8_t> chunk(buffer.data(), n);
      std::size_t data = n;
      Bytes reply;
      if (telnet_) {
        data = reader.take(chunk, commands);
        for (const telnet::Command& command : commands) {
          if (command.verb != telnet::kSb || command.option != telnet::kComPortOption) continue;
          Bytes answer = command.payload;
          if (answer.empty()) continue;
          if (answer[0] == 1 && answer.size() == 5) {
            baud_set = std::uint32_t(answer[1]) << 24 | std::uint32_t(answer[2]) << 16 |
                       std::uint32_t(answer[3]) << 8 | answer[4];
            if (baud_answered != 0) {
              const std::uint32_t b = baud_answered;
              answer = {1, std::uint8_t(b >> 24), std::uint8_t(b >> 16), std::uint8_t(b >> 8),
                        std::uint8_t(b)};
            }
          }
          answer[0] = std::uint8_t(answer[0] + 100);
          const Bytes wire = telnet::subnegotiation(telnet::kComPortOption, answer);
          reply.insert(reply.end(), wire.begin(), wire.end());
        }
        commands.clear();
      }
      Bytes echoed;
      for (std::size_t i = 0; i < data; ++i) echoed.push_back(std::uint8_t(chunk[i] + 1));
      if (telnet_) {
        telnet::escape(echoed, reply);
      } else {
        reply.insert(reply.end(), echoed.begin(), echoed.end());
      }
      if (reply.empty()) continue;
      co_await asio::async_write(*socket, asio::buffer(reply),
                                 asio::redirect_error(asio::use_awaitable, ec));
      if (ec) co_return;
    }
  }

  asio::ip::tcp::acceptor acceptor_;
  bool telnet_;
  std::shared_ptr<asio::ip::tcp::socket> peer_;
};

SerialLineOptions options_for(const std::string& url) {
  SerialLineOptions o;
  o.name = "line1";
  o.port = url;
  o.baud = 62500;
  o.timeout = 200ms;
  o.retries = 0;
  o.late_guard = 100ms;
  o.reopen_min = 20ms;
  o.reopen_max = 40ms;
  return o;
}

asio::awaitable<Result> exchange(SerialLine& line, Bytes request, CountFramer& framer) {
  LineRequest r;
  r.bytes = std::move(request);
  r.framer = &framer;
  co_return co_await line.transact(std::move(r));
}

}  // namespace

TEST_CASE("a line on a raw TCP device server moves the bytes as they are") {
  asio::io_context io;
  ScriptedServer server(io, false);
  auto line = tiltgate::make_serial_line(io.get_executor(), options_for(server.url()));
  CHECK_FALSE(line->start());  // connecting
  CountFramer framer(3);
  const Result result =
      tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x01, 0xFE, 0x10}, framer));
  REQUIRE(result);
  CHECK(framer.bytes == Bytes{0x02, 0xFF, 0x11});
  CHECK(server.raw_received == Bytes{0x01, 0xFE, 0x10});
  CHECK(line->generation() == 1);
  REQUIRE(line->last_timing().reply_delay);
}

TEST_CASE("a line on an RFC 2217 server sets the rate, and escapes 0xFF both ways") {
  asio::io_context io;
  ScriptedServer server(io, true);
  auto line = tiltgate::make_serial_line(io.get_executor(), options_for(server.url()));
  line->start();
  CountFramer framer(2);
  const Result result =
      tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0xFF, 0xFE}, framer));
  REQUIRE(result);
  CHECK(server.baud_set == 62500u);
  CHECK(framer.bytes == Bytes{0x00, 0xFF});  // 0xFF + 1 wraps; 0xFE + 1 came doubled
  // The request's 0xFF went doubled, after the negotiation.
  REQUIRE(server.raw_received.size() >= 3);
  CHECK(Bytes(server.raw_received.end() - 3, server.raw_received.end()) == Bytes{0xFF, 0xFF, 0xFE});
}

TEST_CASE("a server that sets another rate than asked leaves the line closed") {
  asio::io_context io;
  ScriptedServer server(io, true);
  server.baud_answered = 9600;
  auto line = tiltgate::make_serial_line(io.get_executor(), options_for(server.url()));
  line->start();
  CountFramer framer(1);
  const Result result = tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x01}, framer));
  REQUIRE_FALSE(result);
  CHECK(result.error() == LineError::closed);
  CHECK(server.baud_set == 62500u);
  CHECK_FALSE(line->is_open());
}

TEST_CASE("a lost connection closes the line, and it connects again by itself") {
  asio::io_context io;
  ScriptedServer server(io, false);
  auto line = tiltgate::make_serial_line(io.get_executor(), options_for(server.url()));
  line->start();
  CountFramer framer(1);
  REQUIRE(tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x01}, framer)));
  server.drop();
  const Result lost = tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x02}, framer));
  REQUIRE_FALSE(lost);
  CHECK((lost.error() == LineError::io || lost.error() == LineError::closed));
  // The line is open when its connect completes, which can be before the server's accept
  // has run in the same io_context: wait for both sides.
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while ((!line->is_open() || server.connections < 2) &&
         std::chrono::steady_clock::now() < deadline) {
    tiltgate::test::run_for(io, 10ms);
  }
  REQUIRE(line->is_open());
  CHECK(line->generation() == 2);
  CHECK(line->stats().reopens == 1);
  CHECK(server.connections == 2);
  REQUIRE(tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x05}, framer)));
  CHECK(framer.bytes == Bytes{0x06});
}

TEST_CASE("a refused connection is retried with back-off until the server is there") {
  asio::io_context io;
  // A port nobody listens on: take one and give it back.
  std::uint16_t free_port = 0;
  {
    asio::ip::tcp::acceptor probe(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    free_port = probe.local_endpoint().port();
  }
  auto line = tiltgate::make_serial_line(
      io.get_executor(), options_for("tcp://127.0.0.1:" + std::to_string(free_port)));
  line->start();
  CountFramer framer(1);
  const Result refused = tiltgate::test::run_coroutine(io, exchange(*line, Bytes{0x01}, framer));
  REQUIRE_FALSE(refused);
  CHECK(refused.error() == LineError::closed);
  CHECK(line->generation() == 0);
}
