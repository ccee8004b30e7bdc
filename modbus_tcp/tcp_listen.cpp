#include "modbus_tcp/tcp_listen.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "modbus_tcp/inherited_sockets.h"

namespace tiltgate {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

Expected<Done, std::string> listen_on(tcp::acceptor& acceptor, const std::string& listen,
                                      std::uint16_t port, std::string_view what) {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(listen, ec);
  if (ec) return Unexpected{fmt::format("listen address '{}' is not an IP address", listen)};
  const tcp::endpoint endpoint(address, port);
  if (auto inherited = take_inherited_listener(port)) {
    // systemd bound it (ListenStream= in a .socket unit), so no privilege is needed here; its
    // address is the unit's to choose.
    acceptor.assign(inherited->ipv6 ? tcp::v6() : tcp::v4(), inherited->fd, ec);
    if (ec)
      return Unexpected{fmt::format("cannot use the socket systemd passed for {} port {}: {}",
                                    what, port, ec.message())};
    spdlog::info("{}: serving on the socket systemd passed for port {}", what, port);
    return Done{};
  }
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
  if (ec == boost::system::errc::permission_denied && port < 1024)
    return Unexpected{fmt::format(
        "cannot bind {} {}:{}: {}; a port below 1024 needs root, CAP_NET_BIND_SERVICE or a "
        "systemd socket (docs/operations.md, \"Running without root\")",
        what, listen, port, ec.message())};
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

std::string peer_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  if (ec) return "(unknown peer)";
  const asio::ip::address address = canonical_ip(peer.address());
  if (address.is_v6()) return fmt::format("[{}]:{}", address.to_string(), peer.port());
  return fmt::format("{}:{}", address.to_string(), peer.port());
}

std::string address_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  return ec ? "(unknown peer)" : canonical_address(peer.address());
}

}  // namespace tiltgate
