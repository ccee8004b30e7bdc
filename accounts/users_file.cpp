// Looking up, checking and editing the accounts, and writing the file back.
#include "accounts/users_file.h"

#include <algorithm>
#include <fmt/format.h>

#include "accounts/password_hash.h"
#include "store/whole_file_write.h"

namespace tiltgate {

namespace {

// The first lines of a file `tiltgate user add` makes.
constexpr std::string_view kNewFileHeader[] = {
    "# tiltgate web console accounts: NAME:ROLE:HASH, ROLE viewer, operator or admin, HASH argon2id.",
    "# Edit with `tiltgate user add|passwd|remove|list` (docs/web-console.md, \"Accounts\").",
};

Expected<std::string, std::string> hash_of_new_password(std::string_view password) {
  if (password.empty()) return Unexpected(std::string("an empty password is refused"));
  std::string hash = hash_password(password);
  if (hash.empty())
    return Unexpected(fmt::format("the password could not be hashed (argon2id needs {} MiB)",
                                  kPasswordHashMemoryBytes / (1024 * 1024)));
  return hash;
}

std::string no_account(std::string_view name) { return fmt::format("no account named {}", name); }

}  // namespace

const UserAccount* UsersFile::find(std::string_view name) const {
  auto it = std::find_if(accounts_.begin(), accounts_.end(),
                         [name](const UserAccount& account) { return account.name == name; });
  return it == accounts_.end() ? nullptr : &*it;
}

UserAccount* UsersFile::find_mutable(std::string_view name) {
  return const_cast<UserAccount*>(std::as_const(*this).find(name));
}

std::optional<Role> UsersFile::verify(std::string_view name, std::string_view password) const {
  const UserAccount* account = find(name);
  // One verification either way: an unknown name costs what a known one does.
  const bool right = verify_password(account ? account->hash : unknown_user_hash(), password);
  if (!account || !right) return std::nullopt;
  return account->role;
}

Expected<Done, std::string> UsersFile::add(std::string name, Role role,
                                           std::string_view password) {
  if (!valid_user_name(name))
    return Unexpected(fmt::format("user name \"{}\" is not 1 to 64 of A-Z a-z 0-9 . _ @ -", name));
  if (find(name) != nullptr)
    return Unexpected(fmt::format("an account named {} exists already (`tiltgate user passwd {}` "
                                  "changes its password)",
                                  name, name));
  auto hash = hash_of_new_password(password);
  if (!hash) return Unexpected(hash.error());
  if (lines_.empty())
    for (std::string_view header : kNewFileHeader) lines_.push_back({false, std::string(header)});
  lines_.push_back({true, name});
  accounts_.push_back({std::move(name), role, std::move(*hash)});
  return Done{};
}

Expected<Done, std::string> UsersFile::set_password(std::string_view name,
                                                    std::string_view password) {
  UserAccount* account = find_mutable(name);
  if (account == nullptr) return Unexpected(no_account(name));
  auto hash = hash_of_new_password(password);
  if (!hash) return Unexpected(hash.error());
  account->hash = std::move(*hash);
  return Done{};
}

Expected<Done, std::string> UsersFile::set_role(std::string_view name, Role role) {
  UserAccount* account = find_mutable(name);
  if (account == nullptr) return Unexpected(no_account(name));
  account->role = role;
  return Done{};
}

Expected<Done, std::string> UsersFile::remove(std::string_view name) {
  if (find(name) == nullptr) return Unexpected(no_account(name));
  std::erase_if(accounts_, [name](const UserAccount& account) { return account.name == name; });
  std::erase_if(lines_, [name](const Line& line) { return line.is_account && line.text == name; });
  return Done{};
}

std::string UsersFile::text() const {
  std::string text;
  for (const Line& line : lines_) {
    if (!line.is_account) {
      text += line.text;
    } else if (const UserAccount* account = find(line.text)) {
      text += fmt::format("{}:{}:{}", account->name, role_name(account->role), account->hash);
    }
    text += '\n';
  }
  return text;
}

Expected<Done, std::string> UsersFile::save(const std::string& path) const {
  return write_whole_file(path, text(), 0640, FileMode::given);
}

}  // namespace tiltgate
