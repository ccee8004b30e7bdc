#include "accounts/role.h"

#include <array>

namespace tiltgate {

namespace {

constexpr std::array<Role, 3> kRoles = {Role::viewer, Role::operator_, Role::admin};

}  // namespace

std::string_view role_name(Role role) {
  switch (role) {
    case Role::viewer: return "viewer";
    case Role::operator_: return "operator";
    case Role::admin: return "admin";
  }
  return "viewer";  // not reached: every enumerator is named above
}

std::optional<Role> parse_role(std::string_view name) {
  for (Role role : kRoles)
    if (role_name(role) == name) return role;
  return std::nullopt;
}

}  // namespace tiltgate
