// The console's accounts (docs/web-console.md, "Accounts"): the users file, one account a line
// as NAME:ROLE:HASH, with `#` comments and blank lines, which an edit keeps where they are.
// No password is ever in it, nor in any error or log line made from it: only argon2id hashes
// (accounts/password_hash.h), and a line that is not one is reported by its number alone.
// A malformed line is skipped, not the whole file (docs/web-console.md, "The users file"): the
// other accounts keep working, and the account it names, if it names one, has no login.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "accounts/role.h"
#include "driver/expected.h"

namespace tiltgate {

struct UserAccount {
  std::string name;
  Role role;
  std::string hash;
};

// 1 to 64 characters of A-Z, a-z, 0-9, '.', '_', '@' and '-': no ':' (the file's separator),
// no space, nothing a log line or a shell would read otherwise.
bool valid_user_name(std::string_view name);

class UsersFile {
 public:
  UsersFile() = default;  // no account, as `tiltgate user add` starts a file

  // The error is a file that cannot be read (a missing one too); its malformed lines are
  // skipped(), not an error.
  static Expected<UsersFile, std::string> load(const std::string& path);
  // The accounts of `text`, read as load() reads the file `path` (which only names it in errors).
  static UsersFile parse(std::string_view text, const std::string& path);

  // The lines that give no account, each "FILE:LINE: what is wrong", in the file's order. The
  // name such a line gives, when it gives a readable one, is no account either, even where
  // another line gives it too: a login must not depend on which of two lines was meant.
  // `tiltgate user` refuses to rewrite a file that has any (text() would drop them).
  const std::vector<std::string>& skipped() const { return skipped_; }

  const std::vector<UserAccount>& accounts() const { return accounts_; }
  const UserAccount* find(std::string_view name) const;
  // The role of `name` when `password` is right. Costs one hash verification whether or not the
  // user exists (unknown_user_hash() for unknown names), so timing does not tell which exist.
  std::optional<Role> verify(std::string_view name, std::string_view password) const;

  Expected<Done, std::string> add(std::string name, Role role, std::string_view password);
  Expected<Done, std::string> set_password(std::string_view name, std::string_view password);
  Expected<Done, std::string> set_role(std::string_view name, Role role);
  Expected<Done, std::string> remove(std::string_view name);

  // Written atomically (a temporary file in the same folder, fsync, rename, fsync the folder),
  // mode 0640, so a crash leaves the old file or the new one, never half of one. The file keeps
  // the owner and group of the one it replaces; a new one takes its folder's group (the
  // package makes /etc/tiltgate the service's group, so the service can read it).
  Expected<Done, std::string> save(const std::string& path) const;

  // The file's text as save() writes it.
  std::string text() const;

 private:
  // One line of the file: an account's (by name) or any other (a comment, a blank) as written.
  struct Line {
    bool is_account = false;
    std::string text;
  };

  UserAccount* find_mutable(std::string_view name);

  std::vector<UserAccount> accounts_;
  std::vector<Line> lines_;
  std::vector<std::string> skipped_;
};

}  // namespace tiltgate
