#include "gateway/tcp_listen.h"

#include <fmt/format.h>

namespace tiltgate {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

Expected<Done, std::string> listen_on(tcp::acceptor& acceptor, const std::string& listen,
                                      std::uint16_t port, std::string_view what) {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(listen, ec);
  if (ec) return Unexpected{fmt::format("listen address '{}' is not an IP address", listen)};
  const tcp::endpoint endpoint(address, port);
  auto failed = [&](const char* step) {
    boost::system::error_code ignored;
    acceptor.close(ignored);
    return Unexpected{fmt::format("cannot {} {} {}:{}: {}", step, what, listen, port, ec.message())};
  };
  acceptor.open(endpoint.protocol(), ec);
  if (ec) return failed("open a socket for");
  // Lets a restarted gateway bind while old connections sit in TIME_WAIT.
  acceptor.set_option(tcp::acceptor::reuse_address(true), ec);
  if (ec) return failed("configure");
  acceptor.bind(endpoint, ec);
  if (ec) return failed("bind");
  acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) return failed("listen on");
  return Done{};
}

boost::asio::ip::address canonical_ip(const boost::asio::ip::address& address) {
  if (address.is_v6() && address.to_v6().is_v4_mapped())
    return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, address.to_v6());
  return address;
}

}  // namespace tiltgate
