#include "redundancy/peer_probe.h"

#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <memory>

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;

const char* to_string(PeerAnswer answer) {
  switch (answer) {
    case PeerAnswer::none: return "does not answer";
    case PeerAnswer::standby: return "answers as the standby";
    case PeerAnswer::active: return "answers as the active gateway";
  }
  return "?";
}

asio::awaitable<PeerAnswer> ask_peer(asio::any_io_executor executor, PeerProbe probe) {
  auto socket = std::make_shared<tcp::socket>(executor);
  tcp::resolver resolver(executor);
  // One deadline for the whole exchange: when it passes, the socket closes under it.
  asio::steady_timer deadline(executor, probe.timeout);
  bool expired = false;
  deadline.async_wait([socket, &expired](const boost::system::error_code& ec) {
    if (ec) return;
    expired = true;
    boost::system::error_code ignored;
    socket->close(ignored);
  });
  boost::system::error_code ec;
  const auto endpoints = co_await resolver.async_resolve(
      probe.host, std::to_string(probe.port), asio::redirect_error(asio::use_awaitable, ec));
  if (ec || expired) co_return PeerAnswer::none;
  co_await asio::async_connect(*socket, endpoints, asio::redirect_error(asio::use_awaitable, ec));
  if (ec || expired) {
    deadline.cancel();
    co_return PeerAnswer::none;
  }
  if (!probe.has_unit) {
    deadline.cancel();
    co_return PeerAnswer::active;  // it answers; what it does cannot be asked
  }
  // MBAP (transaction 1, protocol 0, length 6, unit), FC 02, input 8, one input.
  const std::array<std::uint8_t, 12> request{0, 1, 0, 0, 0, 6, probe.unit_id, 0x02, 0, 8, 0, 1};
  co_await asio::async_write(*socket, asio::buffer(request),
                             asio::redirect_error(asio::use_awaitable, ec));
  // MBAP 7, then FC and byte count, then the input's byte; an exception is FC|0x80 and a code.
  std::array<std::uint8_t, 10> reply{};
  std::size_t got = 0;
  if (!ec)
    got = co_await asio::async_read(*socket, asio::buffer(reply.data(), 9),
                                    asio::redirect_error(asio::use_awaitable, ec));
  const bool bits = !ec && got == 9 && reply[7] == 0x02 && reply[8] == 1;
  if (bits)
    got += co_await asio::async_read(*socket, asio::buffer(reply.data() + 9, 1),
                                     asio::redirect_error(asio::use_awaitable, ec));
  deadline.cancel();
  boost::system::error_code ignored;
  socket->close(ignored);
  if (ec || expired || got < 9) co_return PeerAnswer::none;
  if (!bits || got < 10) co_return PeerAnswer::active;  // it answers, but will not say
  co_return (reply[9] & 1) != 0 ? PeerAnswer::standby : PeerAnswer::active;
}

}  // namespace tiltgate
