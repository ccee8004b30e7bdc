// The byte stream a Modbus TCP connection is served over: the plain socket (port 502) or TLS
// on it (Modbus/TCP Security, port 802). The server's connection logic reads and writes
// through this, so both are served by the same code.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/buffer.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/ssl/stream.hpp>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "driver/expected.h"

namespace tiltgate {

class ModbusStream {
 public:
  explicit ModbusStream(boost::asio::ip::tcp::socket socket);
  ModbusStream(boost::asio::ip::tcp::socket socket, boost::asio::ssl::context& tls);

  bool is_tls() const { return tls_.has_value(); }
  boost::asio::ip::tcp::socket& socket();

  // The TLS handshake (nothing for a plain socket): the client's certificate is checked here.
  boost::asio::awaitable<void> handshake(boost::system::error_code& ec);
  boost::asio::awaitable<std::size_t> read_some(boost::asio::mutable_buffer buffer,
                                                boost::system::error_code& ec);
  boost::asio::awaitable<void> write(boost::asio::const_buffer buffer,
                                     boost::system::error_code& ec);
  // What of `buffer` the socket takes now, without waiting: 0 when it is full, and always 0
  // over TLS (whose records go through write()). `ec` only for a broken connection.
  std::size_t write_now(boost::asio::const_buffer buffer, boost::system::error_code& ec);
  // Closes the socket: what is pending ends with operation_aborted.
  void close();

 private:
  std::optional<boost::asio::ip::tcp::socket> plain_;
  std::optional<boost::asio::ssl::stream<boost::asio::ip::tcp::socket>> tls_;
};

// What Modbus/TCP Security needs of the server ([server] tls): its certificate chain and key,
// and the CA that signs every client's certificate, as PEM text (read when the config loads;
// the file names are for messages).
struct ModbusTlsOptions {
  std::string cert_pem, key_pem, ca_pem;
  std::string cert_file, key_file, ca_file;
  std::uint16_t port = 802;  // 0 picks a free port (tests)
};

// A TLS 1.2+ server context that requires a client certificate signed by the CA; the error
// names the file at fault.
Expected<std::unique_ptr<boost::asio::ssl::context>, std::string> make_tls_context(
    const ModbusTlsOptions& options);

}  // namespace tiltgate
