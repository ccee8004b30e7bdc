// What a console user may do (docs/web-console.md, "Accounts"). The roles are ordered: each
// may do all that the one before it may, so "may this user do X" is `role >= Role::needed`.
#pragma once

#include <optional>
#include <string_view>

namespace tiltgate {

enum class Role {
  viewer,     // sees everything, changes nothing
  operator_,  // also the settings a sensor's map marks as operator settings; info, watch, history
  admin,      // also address, baud, restart, scan, raw frames, the configuration
};

// "viewer", "operator", "admin": as the users file and the command line write them.
std::string_view role_name(Role role);
std::optional<Role> parse_role(std::string_view name);

}  // namespace tiltgate
