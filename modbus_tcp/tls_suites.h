// The TLS versions and cipher suites both TLS servers offer, HTTPS (http/http_server.h) and
// Modbus/TCP Security (modbus_tcp/modbus_stream.h): TLS 1.2 or later, and under TLS 1.2 only
// AEAD suites (AES-GCM, ChaCha20-Poly1305) with a forward-secret key exchange (ECDHE, DHE), as
// Mozilla's "intermediate" server profile lists them. The CBC suites with SHA-1 or SHA-256 MACs
// (AES128-SHA and friends) are refused: their MAC-then-encrypt padding is what Lucky13 and
// POODLE-style attacks work on (issue 52). TLS 1.3 offers only AEAD suites anyway.
#pragma once

#include <openssl/ssl.h>

namespace tiltgate {

// Sets the lowest version and the TLS 1.2 suites on `context`; false: OpenSSL took none of them.
bool offer_only_aead_suites(SSL_CTX* context);

}  // namespace tiltgate
