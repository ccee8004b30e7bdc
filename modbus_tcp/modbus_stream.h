// The bytes of one Modbus TCP connection over its socket: plain TCP (port 502), or TLS on it
// (Modbus/TCP Security, port 802) through OpenSSL. It never waits: the socket is non-blocking,
// and what cannot be done now comes back as would_block, for the connection to try again at
// the socket's next event in its ConnectionLoop (modbus_tcp/connection_loop.h).
#pragma once

#include <openssl/ssl.h>

#include <boost/asio/ssl/context.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "driver/expected.h"
#include "modbus_tcp/client_certificate.h"

namespace tiltgate {

enum class StreamStatus {
  ok,           // `bytes` moved (a read: at least one)
  would_block,  // nothing can move until the socket's next event
  closed,       // the client ended the connection
  failed,       // a socket or TLS error: ModbusStream::error() says which
};

struct StreamResult {
  StreamStatus status = StreamStatus::ok;
  std::size_t bytes = 0;
};

class ModbusStream {
 public:
  // Takes `fd`, a connected TCP socket, and makes it non-blocking; `tls` (a server context
  // from make_tls_context) makes it a TLS stream whose handshake() comes first.
  explicit ModbusStream(int fd, SSL_CTX* tls = nullptr);
  // Closes the socket, if close() did not.
  ~ModbusStream();
  ModbusStream(const ModbusStream&) = delete;
  ModbusStream& operator=(const ModbusStream&) = delete;

  int fd() const { return fd_; }
  bool is_tls() const { return ssl_ != nullptr; }

  // TLS: ok once the handshake is done and the client's certificate checked. A plain stream
  // has none: ok at once.
  StreamResult handshake();
  StreamResult read(std::span<std::uint8_t> into);
  StreamResult write(std::span<const std::uint8_t> bytes);
  // TLS, once handshake() is ok: the certificate the client showed (the CA checked it). None on
  // a plain stream.
  std::optional<ClientCertificate> client_certificate() const;
  // What failed last (failed), for the log.
  const std::string& error() const { return error_; }
  void close();

 private:
  // An OpenSSL call's outcome, from SSL_get_error.
  StreamResult tls_result(int returned);
  StreamResult socket_failure();

  int fd_ = -1;
  SSL* ssl_ = nullptr;
  std::string error_;
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
