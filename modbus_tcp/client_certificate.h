// What a Modbus/TCP Security client's certificate says of it, read once after the handshake:
// its subject, for the log and the audit trail's "who", and its role, for the authorization
// step (config/tls_role_access.h). Pure: OpenSSL's certificate parsing, no socket.
#pragma once

#include <openssl/x509.h>

#include <optional>
#include <string>
#include <string_view>

namespace tiltgate {

// MB-TCP-Security-v21: the RoleOID extension, whose value is the role's name as an ASN.1
// UTF8String.
inline constexpr std::string_view kModbusRoleOid = "1.3.6.1.4.1.50316.802.1";

struct ClientCertificate {
  std::string subject;              // one line, RFC 2253: "CN=plc-1,O=Plant"
  std::optional<std::string> role;  // none: no role extension
  // The role extension is there but holds no UTF8String: the client gets a role no table
  // names ("" here), so it may only read, and this says why for the log.
  std::string role_problem;

  bool operator==(const ClientCertificate&) const = default;
};

ClientCertificate read_client_certificate(const X509& certificate);

}  // namespace tiltgate
