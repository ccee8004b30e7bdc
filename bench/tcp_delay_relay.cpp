#include "bench/tcp_delay_relay.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <deque>
#include <memory>
#include <vector>

namespace tiltgate::bench {

namespace {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

// One direction of one connection: chunks waiting for their time, oldest first.
struct Pipe {
  explicit Pipe(asio::any_io_executor executor) : wake(executor, Clock::time_point::max()) {}
  std::deque<std::pair<Clock::time_point, std::vector<std::uint8_t>>> chunks;
  asio::steady_timer wake;  // cancelled when a chunk arrives, so the writer looks again
  bool ended = false;
};

asio::awaitable<void> read_into(tcp::socket& from, std::shared_ptr<Pipe> pipe,
                                std::chrono::microseconds one_way) {
  std::vector<std::uint8_t> buffer(65536);
  for (;;) {
    boost::system::error_code error;
    const std::size_t n = co_await from.async_read_some(
        asio::buffer(buffer), asio::redirect_error(asio::use_awaitable, error));
    if (error) break;
    pipe->chunks.emplace_back(Clock::now() + one_way,
                              std::vector<std::uint8_t>(buffer.begin(), buffer.begin() + long(n)));
    pipe->wake.cancel();
  }
  pipe->ended = true;
  pipe->wake.cancel();
}

asio::awaitable<void> write_from(std::shared_ptr<Pipe> pipe, tcp::socket& to) {
  for (;;) {
    if (pipe->chunks.empty()) {
      if (pipe->ended) break;
      pipe->wake.expires_at(Clock::time_point::max());
      boost::system::error_code cancelled;
      co_await pipe->wake.async_wait(asio::redirect_error(asio::use_awaitable, cancelled));
      continue;
    }
    auto& [due, bytes] = pipe->chunks.front();
    if (Clock::now() < due) {
      asio::steady_timer timer(to.get_executor(), due);
      boost::system::error_code ignored;
      co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ignored));
    }
    boost::system::error_code error;
    co_await asio::async_write(to, asio::buffer(bytes),
                               asio::redirect_error(asio::use_awaitable, error));
    if (error) break;
    pipe->chunks.pop_front();
  }
  boost::system::error_code ignored;
  to.shutdown(tcp::socket::shutdown_send, ignored);
}

asio::awaitable<void> relay(tcp::socket client, std::uint16_t target_port,
                            std::chrono::microseconds one_way) {
  auto executor = co_await asio::this_coro::executor;
  tcp::socket server(executor);
  boost::system::error_code error;
  co_await server.async_connect({asio::ip::address_v4::loopback(), target_port},
                                asio::redirect_error(asio::use_awaitable, error));
  if (error) co_return;
  client.set_option(tcp::no_delay(true));
  server.set_option(tcp::no_delay(true));
  auto up = std::make_shared<Pipe>(executor);
  auto down = std::make_shared<Pipe>(executor);
  auto sockets = std::make_shared<std::pair<tcp::socket, tcp::socket>>(std::move(client),
                                                                       std::move(server));
  // The sockets live as long as any of the four coroutines does.
  auto keep = [sockets](std::exception_ptr) {};
  asio::co_spawn(executor, read_into(sockets->first, up, one_way), keep);
  asio::co_spawn(executor, write_from(up, sockets->second), keep);
  asio::co_spawn(executor, read_into(sockets->second, down, one_way), keep);
  asio::co_spawn(executor, write_from(down, sockets->first), keep);
}

asio::awaitable<void> accept_all(tcp::acceptor& acceptor, std::uint16_t target_port,
                                 std::chrono::microseconds one_way) {
  for (;;) {
    boost::system::error_code error;
    tcp::socket socket = co_await acceptor.async_accept(
        asio::redirect_error(asio::use_awaitable, error));
    if (error) co_return;
    asio::co_spawn(acceptor.get_executor(), relay(std::move(socket), target_port, one_way),
                   asio::detached);
  }
}

}  // namespace

TcpDelayRelay::TcpDelayRelay(std::uint16_t target_port, std::chrono::microseconds one_way) {
  auto acceptor = std::make_shared<tcp::acceptor>(
      io_, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
  port_ = acceptor->local_endpoint().port();
  asio::co_spawn(io_, accept_all(*acceptor, target_port, one_way),
                 [acceptor](std::exception_ptr) {});
  thread_ = std::thread([this] { io_.run(); });
}

TcpDelayRelay::~TcpDelayRelay() {
  io_.stop();
  thread_.join();
}

}  // namespace tiltgate::bench
