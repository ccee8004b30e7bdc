#include "sim/support/serial_line_bench.h"

#include <doctest/doctest.h>

#include <array>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <optional>
#include <utility>

#include "sim/support/termios2_skip.h"

namespace tiltgate::test::line_bench {

namespace asio = boost::asio;
using namespace std::chrono_literals;
using tiltgate::LineRequest;
using tiltgate::PseudoTerminal;
using tiltgate::SerialLine;
using tiltgate::SerialLineOptions;

Bytes bytes_of(const std::string& text) { return Bytes(text.begin(), text.end()); }

PseudoTerminal open_pty() {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  return std::move(*pty);
}

FarEnd::FarEnd(asio::io_context& io, PseudoTerminal& pty) : port_(io, pty.release_master()) {}

asio::awaitable<Bytes> FarEnd::receive(std::size_t size) {
  Bytes bytes(size);
  co_await asio::async_read(port_, asio::buffer(bytes), asio::use_awaitable);
  arrivals.push_back(Clock::now());
  co_return bytes;
}

asio::awaitable<void> FarEnd::send(Bytes bytes) {
  co_await asio::async_write(port_, asio::buffer(bytes), asio::use_awaitable);
}

asio::awaitable<void> FarEnd::listen_silently() {
  std::array<std::uint8_t, 64> buffer{};
  for (boost::system::error_code ec; !ec;) {
    received += co_await port_.async_read_some(asio::buffer(buffer),
                                               asio::redirect_error(asio::use_awaitable, ec));
  }
}

SerialLineOptions options_for(const std::string& port) {
  SerialLineOptions o;
  o.name = "line1";
  o.port = port;
  // A standard rate (the product's default is 125000): the line's tests then also run on a port
  // without termios2, as under qemu (sim/support/termios2_skip.h).
  o.baud = 115200;
  o.timeout = 2000ms;  // generous: only the silent-device tests wait it out, with their own
  o.retries = 0;
  o.late_guard = 50ms;  // short: only the late-reply tests wait it out, with their own
  o.gap = 1000us;
  o.reopen_min = 10ms;
  o.reopen_max = 40ms;
  return o;
}

bool run_until(asio::io_context& io, const std::function<bool()>& done, Clock::duration limit) {
  const auto deadline = Clock::now() + limit;
  io.restart();  // an io_context that ran out of work earlier stays stopped until restarted
  while (!done() && Clock::now() < deadline) io.run_one_for(deadline - Clock::now());
  return done();
}

asio::awaitable<bool> eventually(std::function<bool()> condition, Clock::duration limit) {
  asio::steady_timer timer(co_await asio::this_coro::executor);
  const auto deadline = Clock::now() + limit;
  while (!condition()) {
    if (Clock::now() >= deadline) co_return false;
    timer.expires_after(1ms);
    co_await timer.async_wait(asio::use_awaitable);
  }
  co_return true;
}

Result transact(asio::io_context& io, SerialLine& line, LineRequest request) {
  std::optional<Result> result;
  auto body = [&]() -> asio::awaitable<void> {
    result = co_await line.transact(std::move(request));
  };
  asio::co_spawn(io, body(), asio::detached);
  REQUIRE_MESSAGE(run_until(io, [&] { return result.has_value(); }), "transact did not end");
  return *result;
}

LineRequest request_of(Bytes bytes, tiltgate::ReplyFramer* framer) {
  LineRequest r;
  r.bytes = std::move(bytes);
  r.framer = framer;
  return r;
}

Bench::Bench(const std::function<void(SerialLineOptions&)>& adjust) {
  SerialLineOptions options = options_for(pty.slave_path());
  if (adjust) adjust(options);
  tiltgate::test::skip_unless_settable(options);
  line = std::make_unique<SerialLine>(io.get_executor(), options);
  REQUIRE(line->start());
}

Result Bench::transact(LineRequest request) {
  return line_bench::transact(io, *line, std::move(request));
}

Result Bench::exchange(LineRequest request, asio::awaitable<void> device) {
  asio::co_spawn(io, std::move(device), asio::detached);
  return transact(std::move(request));
}

asio::awaitable<void> pause(Clock::duration how_long) {
  asio::steady_timer timer(co_await asio::this_coro::executor, how_long);
  co_await timer.async_wait(asio::use_awaitable);
}

}  // namespace tiltgate::test::line_bench
