#include "app/demo_accounts.h"

#include "accounts/random_password.h"
#include "accounts/users_file.h"

namespace tiltgate {

Expected<std::vector<DemoAccount>, std::string> make_demo_accounts(
    const std::filesystem::path& users_file) {
  std::vector<DemoAccount> accounts;
  UsersFile file;
  for (const Role role : {Role::admin, Role::operator_, Role::viewer}) {
    DemoAccount account{std::string(role_name(role)), role, random_password()};
    if (account.password.empty()) return Unexpected{std::string("cannot make a password")};
    if (auto added = file.add(account.name, role, account.password); !added)
      return Unexpected{added.error()};
    accounts.push_back(std::move(account));
  }
  if (auto saved = file.save(users_file.string()); !saved) return Unexpected{saved.error()};
  return accounts;
}

}  // namespace tiltgate
