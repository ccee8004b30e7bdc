// Modbus/TCP Security's authorization step ([server] tls_role_access, tls_no_role_access): what
// a TLS client may do, from the role its certificate names in the role extension
// (MB-TCP-Security-v21: the RoleOID extension, 1.3.6.1.4.1.50316.802.1, a UTF8String). Plain
// data: the config fills it, the Modbus TCP server asks it at each write.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>

namespace tiltgate {

enum class ClientAccess { read_only, read_write };

struct TlsRoleAccess {
  std::map<std::string, ClientAccess, std::less<>> roles;  // role name -> access
  // A certificate without the role extension: read-write, as before roles were read, so a
  // plant's existing client certificates keep their rights.
  ClientAccess no_role = ClientAccess::read_write;

  // The access of a client whose certificate names `role` (none: it has no role extension).
  // A role the table does not name may only read.
  ClientAccess of(const std::optional<std::string>& role) const {
    if (!role) return no_role;
    const auto found = roles.find(*role);
    return found == roles.end() ? ClientAccess::read_only : found->second;
  }
  bool knows(const std::string& role) const { return roles.contains(role); }

  bool operator==(const TlsRoleAccess&) const = default;
};

}  // namespace tiltgate
