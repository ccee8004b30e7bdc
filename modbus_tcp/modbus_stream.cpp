#include "modbus_tcp/modbus_stream.h"

#include <openssl/ssl.h>

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/ssl/error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;

ModbusStream::ModbusStream(tcp::socket socket) : plain_(std::move(socket)) {
  // write() tries the socket at once and must not block when the client's window is full.
  boost::system::error_code ec;
  plain_->non_blocking(true, ec);
}

ModbusStream::ModbusStream(tcp::socket socket, asio::ssl::context& tls)
    : tls_(std::in_place, std::move(socket), tls) {}

tcp::socket& ModbusStream::socket() { return tls_ ? tls_->next_layer() : *plain_; }

asio::awaitable<void> ModbusStream::handshake(boost::system::error_code& ec) {
  if (!tls_) co_return;
  co_await tls_->async_handshake(asio::ssl::stream_base::server,
                                 asio::redirect_error(asio::use_awaitable, ec));
}

asio::awaitable<std::size_t> ModbusStream::read_some(asio::mutable_buffer buffer,
                                                     boost::system::error_code& ec) {
  // The socket's own operation, not a coroutine around it: a coroutine frame less per read,
  // which Boost 1.74 would allocate (docs/performance.md, "The Modbus read path").
  if (tls_) return tls_->async_read_some(buffer, asio::redirect_error(asio::use_awaitable, ec));
  return plain_->async_read_some(buffer, asio::redirect_error(asio::use_awaitable, ec));
}

asio::awaitable<void> ModbusStream::write(asio::const_buffer buffer,
                                          boost::system::error_code& ec) {
  if (tls_) {
    co_await asio::async_write(*tls_, buffer, asio::redirect_error(asio::use_awaitable, ec));
    co_return;
  }
  // A reply almost always fits the socket's send buffer: one send() now. An async_write that
  // completes at once still posts its completion, and the event loop polls epoll once more
  // before running it; only what did not fit waits for the socket.
  const std::size_t sent = write_now(buffer, ec);
  if (ec || sent == buffer.size()) co_return;
  buffer += sent;
  co_await asio::async_write(*plain_, buffer, asio::redirect_error(asio::use_awaitable, ec));
}

std::size_t ModbusStream::write_now(asio::const_buffer buffer, boost::system::error_code& ec) {
  ec = {};
  if (tls_) return 0;
  const std::size_t sent = plain_->write_some(buffer, ec);
  if (ec == asio::error::would_block || ec == asio::error::try_again) ec = {};
  return ec ? 0 : sent;
}

void ModbusStream::close() {
  boost::system::error_code ec;
  socket().close(ec);
}

Expected<std::unique_ptr<asio::ssl::context>, std::string> make_tls_context(
    const ModbusTlsOptions& options) {
  auto context = std::make_unique<asio::ssl::context>(asio::ssl::context::tls_server);
  // Modbus/TCP Security (MB-TCP-Security-v21, R-01): TLS 1.2 or later, mutual authentication.
  SSL_CTX_set_min_proto_version(context->native_handle(), TLS1_2_VERSION);
  context->set_options(asio::ssl::context::default_workarounds |
                       asio::ssl::context::single_dh_use);
  boost::system::error_code ec;
  context->use_certificate_chain(asio::buffer(options.cert_pem), ec);
  if (ec) return Unexpected("TLS certificate " + options.cert_file + ": " + ec.message());
  context->use_private_key(asio::buffer(options.key_pem), asio::ssl::context::pem, ec);
  if (ec) return Unexpected("TLS key " + options.key_file + ": " + ec.message());
  if (SSL_CTX_check_private_key(context->native_handle()) != 1)
    return Unexpected("TLS key " + options.key_file + " does not belong to the certificate " +
                      options.cert_file);
  context->add_certificate_authority(asio::buffer(options.ca_pem), ec);
  if (ec) return Unexpected("TLS CA " + options.ca_file + ": " + ec.message());
  context->set_verify_mode(asio::ssl::verify_peer | asio::ssl::verify_fail_if_no_peer_cert);
  return context;
}

}  // namespace tiltgate
