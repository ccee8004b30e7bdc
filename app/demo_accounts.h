// The demo's web console accounts (docs/web-console.md, "Try it"): admin, operator and viewer,
// each with a password made for this run, in a users file in the demo's temporary folder, gone
// when the demo stops. What the demo prints beside its mbpoll lines.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "accounts/role.h"
#include "driver/expected.h"

namespace tiltgate {

struct DemoAccount {
  std::string name;  // the role's name: "admin", "operator", "viewer"
  Role role;
  std::string password;
};

// Writes the three accounts to `users_file`; what went wrong otherwise.
Expected<std::vector<DemoAccount>, std::string> make_demo_accounts(
    const std::filesystem::path& users_file);

}  // namespace tiltgate
