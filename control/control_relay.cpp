#include "control/control_relay.h"

#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <istream>
#include <memory>
#include <string>
#include <variant>

#include "control/control_protocol.h"
#include "control/control_socket_io.h"

namespace tiltgate {

namespace asio = boost::asio;

void ControlRelayFramer::reset() {
  received_.clear();
  // A deadline of now: sent if the socket takes it at once, never waited for.
  if (!broken_ && !control::send_line(socket_.native_handle(),
                                      control::format(control::GatewayMessage{control::Reset{}}),
                                      std::chrono::steady_clock::now()))
    broken_ = true;
}

bool ControlRelayFramer::feed(std::span<const std::uint8_t>) {
  broken_ = true;
  return false;
}

asio::awaitable<bool> ControlRelayFramer::feed_async(std::span<const std::uint8_t> bytes) {
  if (broken_ || bytes.empty()) co_return false;
  received_.insert(received_.end(), bytes.begin(), bytes.end());
  // Formatted before the co_await: g++ 12 destroys a braced temporary there twice.
  const std::string line =
      control::format(control::GatewayMessage{control::Received{{bytes.begin(), bytes.end()}}}) +
      "\n";
  // Too slow: the socket's operations are cancelled, which ends the exchange below. `done`
  // keeps a wait that expired as the answer came from cancelling anything after it.
  auto done = std::make_shared<bool>(false);
  asio::steady_timer bound(socket_.get_executor(), kAnswerWait);
  bound.async_wait([done, socket = &socket_](const boost::system::error_code& ec) {
    if (!ec && !*done) socket->cancel();
  });
  boost::system::error_code ec;
  co_await asio::async_write(socket_, asio::buffer(line),
                             asio::redirect_error(asio::use_awaitable, ec));
  if (!ec)
    co_await asio::async_read_until(socket_, input_, '\n',
                                    asio::redirect_error(asio::use_awaitable, ec));
  *done = true;
  bound.cancel();
  if (!ec) {
    std::string answer;
    std::istream stream(&input_);
    std::getline(stream, answer);
    if (const auto parsed = control::parse_command(answer))
      if (const auto* verdict = std::get_if<control::FramerAnswer>(&*parsed))
        co_return verdict->done;
  }
  broken_ = true;  // gone, too slow, or not an answer
  co_return false;
}

}  // namespace tiltgate
