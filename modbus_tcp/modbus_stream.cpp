#include "modbus_tcp/modbus_stream.h"
#include "modbus_tcp/tls_suites.h"

#include <fcntl.h>
#include <openssl/err.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace tiltgate {

namespace asio = boost::asio;

ModbusStream::ModbusStream(int fd, SSL_CTX* tls) : fd_(fd) {
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
  if (tls == nullptr) return;
  ssl_ = SSL_new(tls);
  if (ssl_ == nullptr) {
    error_ = "TLS: out of memory";
    return;
  }
  SSL_set_fd(ssl_, fd_);
  SSL_set_accept_state(ssl_);
  // A reply the socket takes in part is written on from where it stopped, from the
  // connection's buffer, which may have moved by then.
  SSL_set_mode(ssl_, SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER);
}

ModbusStream::~ModbusStream() { close(); }

void ModbusStream::close() {
  if (ssl_ != nullptr) SSL_free(ssl_);
  ssl_ = nullptr;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

StreamResult ModbusStream::socket_failure() {
  if (errno == EAGAIN || errno == EWOULDBLOCK) return {StreamStatus::would_block};
  error_ = std::strerror(errno);
  return {errno == ECONNRESET || errno == EPIPE ? StreamStatus::closed : StreamStatus::failed};
}

StreamResult ModbusStream::tls_result(int returned) {
  if (returned > 0) return {StreamStatus::ok, std::size_t(returned)};
  switch (SSL_get_error(ssl_, returned)) {
    case SSL_ERROR_WANT_READ:
    case SSL_ERROR_WANT_WRITE: return {StreamStatus::would_block};
    case SSL_ERROR_ZERO_RETURN: return {StreamStatus::closed};
    case SSL_ERROR_SYSCALL:
      if (ERR_peek_error() == 0) {
        if (errno == 0) return {StreamStatus::closed};  // end of file without close_notify
        return socket_failure();
      }
      [[fallthrough]];
    default: {
      char text[256];
      ERR_error_string_n(ERR_get_error(), text, sizeof text);
      error_ = text;
      ERR_clear_error();
      return {StreamStatus::failed};
    }
  }
}

StreamResult ModbusStream::handshake() {
  if (ssl_ == nullptr) return {error_.empty() ? StreamStatus::ok : StreamStatus::failed};
  ERR_clear_error();
  errno = 0;
  const int done = SSL_do_handshake(ssl_);
  return done == 1 ? StreamResult{StreamStatus::ok} : tls_result(done);
}

std::optional<ClientCertificate> ModbusStream::client_certificate() const {
  if (ssl_ == nullptr) return std::nullopt;
  const X509* certificate = SSL_get0_peer_certificate(ssl_);
  if (certificate == nullptr) return std::nullopt;  // none without verify_fail_if_no_peer_cert
  return read_client_certificate(*certificate);
}

StreamResult ModbusStream::read(std::span<std::uint8_t> into) {
  if (ssl_ != nullptr) {
    ERR_clear_error();
    errno = 0;
    return tls_result(SSL_read(ssl_, into.data(), int(into.size())));
  }
  for (;;) {
    const ssize_t n = ::recv(fd_, into.data(), into.size(), 0);
    if (n > 0) return {StreamStatus::ok, std::size_t(n)};
    if (n == 0) return {StreamStatus::closed};
    if (errno != EINTR) return socket_failure();
  }
}

StreamResult ModbusStream::write(std::span<const std::uint8_t> bytes) {
  if (ssl_ != nullptr) {
    ERR_clear_error();
    errno = 0;
    return tls_result(SSL_write(ssl_, bytes.data(), int(bytes.size())));
  }
  for (;;) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n >= 0) return {StreamStatus::ok, std::size_t(n)};
    if (errno != EINTR) return socket_failure();
  }
}

Expected<std::unique_ptr<asio::ssl::context>, std::string> make_tls_context(
    const ModbusTlsOptions& options) {
  auto context = std::make_unique<asio::ssl::context>(asio::ssl::context::tls_server);
  // Modbus/TCP Security (MB-TCP-Security-v21, R-01): TLS 1.2 or later, mutual authentication;
  // under TLS 1.2 the AEAD suites only (modbus_tcp/tls_suites.h).
  if (!offer_only_aead_suites(context->native_handle()))
    return Unexpected(std::string("TLS: OpenSSL offers none of the AEAD cipher suites"));
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
