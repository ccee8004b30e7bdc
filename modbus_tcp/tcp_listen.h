// Opening a TCP listener the way every server of the gateway does (Modbus TCP, HTTP): an IP
// address literal and a port, SO_REUSEADDR, and one message naming the step that failed.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

// Binds and listens `acceptor` on `listen`:`port`; on failure it is left closed and the error
// reads "cannot bind WHAT 127.0.0.1:502: Address already in use". A listening socket systemd
// passed for `port` (socket activation) is taken instead of binding a new one.
Expected<Done, std::string> listen_on(boost::asio::ip::tcp::acceptor& acceptor,
                                      const std::string& listen, std::uint16_t port,
                                      std::string_view what);

// A peer's address as the allow lists and per-host limits see it: an IPv4 client of a
// dual-stack socket (::ffff:a.b.c.d) is its IPv4 address.
boost::asio::ip::address canonical_ip(const boost::asio::ip::address& address);
inline std::string canonical_address(const boost::asio::ip::address& address) {
  return canonical_ip(address).to_string();
}

// A connected socket's peer for the log, "127.0.0.1:50312" or "[::1]:50312"; "(unknown peer)"
// when it has gone already.
std::string peer_of(const boost::asio::ip::tcp::socket& socket);
// Its address without the port (canonical_address()): what a flood of connections has in
// common, and what max_clients_per_host counts.
std::string address_of(const boost::asio::ip::tcp::socket& socket);

}  // namespace tiltgate
