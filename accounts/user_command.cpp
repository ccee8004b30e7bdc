// Each action loads the file, changes one account and saves it whole (atomically); the
// password is read after the checks that need none, so a mistake costs no typing.
#include "accounts/user_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "accounts/password_input.h"
#include "accounts/password_rules.h"
#include "accounts/users_file.h"

namespace tiltgate {

namespace {

constexpr int kOk = 0;
constexpr int kFailed = 1;

struct UserOptions {
  std::string action;
  std::string name;
  std::string role = "viewer";
  std::string users_file = "/etc/tiltgate/users";
  bool allow_weak = false;  // --allow-weak: no password rules (test rigs)
};

int failed(const std::string& message) {
  std::cerr << message << "\n";
  return kFailed;
}

int saved(const UsersFile& file, const std::string& path, const std::string& done) {
  if (auto written = file.save(path); !written) return failed(written.error());
  std::cout << fmt::format("{}: {}\n", path, done);
  return kOk;
}

// The new password, read and held to the rules (accounts/password_rules.h) unless
// --allow-weak; the reason, with how to go on, when it is refused.
Expected<std::string, std::string> new_password(const UserOptions& options) {
  auto password = read_new_password(options.name);
  if (!password || options.allow_weak) return password;
  if (auto weakness = password_weakness(options.name, *password))
    return Unexpected(fmt::format("password refused: {} (a longer one, or --allow-weak on a test "
                                  "rig)",
                                  *weakness));
  return password;
}

// `add` starts a file when there is none; every other action needs it. A file with a malformed
// line is refused, for `list` too: it names the lines to fix (docs/web-console.md, "The users
// file").
Expected<UsersFile, std::string> file_for(const UserOptions& options) {
  std::error_code ec;
  if (options.action == "add" && !std::filesystem::exists(options.users_file, ec) && !ec)
    return UsersFile{};
  auto file = UsersFile::load(options.users_file);
  // Saving rewrites the file from its accounts: a malformed line would be lost without a word,
  // and it may be an account someone mistyped. Fixing it is a hand edit.
  if (file && !file->skipped().empty())
    return Unexpected(fmt::format("{}\n{}: fix or delete the line(s) above by hand first: "
                                  "`tiltgate user` rewrites the whole file and would drop them",
                                  fmt::join(file->skipped(), "\n"), options.users_file));
  return file;
}

int add(UsersFile& file, const UserOptions& options) {
  if (file.find(options.name) != nullptr)
    return failed(fmt::format("{}: an account named {} exists already (`tiltgate user passwd {}` "
                              "changes its password)",
                              options.users_file, options.name, options.name));
  auto password = new_password(options);
  if (!password) return failed(password.error());
  const Role role = *parse_role(options.role);  // checked by CLI11
  if (auto added = file.add(options.name, role, *password); !added) return failed(added.error());
  return saved(file, options.users_file,
               fmt::format("added {} ({})", options.name, role_name(role)));
}

int passwd(UsersFile& file, const UserOptions& options) {
  if (file.find(options.name) == nullptr)
    return failed(fmt::format("{}: no account named {}", options.users_file, options.name));
  auto password = new_password(options);
  if (!password) return failed(password.error());
  if (auto set = file.set_password(options.name, *password); !set) return failed(set.error());
  return saved(file, options.users_file, fmt::format("new password for {}", options.name));
}

int set_role(UsersFile& file, const UserOptions& options) {
  const Role role = *parse_role(options.role);  // checked by CLI11
  if (auto set = file.set_role(options.name, role); !set)
    return failed(fmt::format("{}: {}", options.users_file, set.error()));
  return saved(file, options.users_file,
               fmt::format("{} is now {}", options.name, role_name(role)));
}

int remove(UsersFile& file, const UserOptions& options) {
  if (auto removed = file.remove(options.name); !removed)
    return failed(fmt::format("{}: {}", options.users_file, removed.error()));
  return saved(file, options.users_file, fmt::format("removed {}", options.name));
}

// Names and roles, never a hash.
int list(const UsersFile& file) {
  std::size_t width = 4;
  for (const UserAccount& account : file.accounts()) width = std::max(width, account.name.size());
  for (const UserAccount& account : file.accounts())
    std::cout << fmt::format("{:<{}}  {}\n", account.name, width, role_name(account.role));
  return kOk;
}

int user_command(const UserOptions& options) {
  auto file = file_for(options);
  if (!file) return failed(file.error());
  if (options.action == "add") return add(*file, options);
  if (options.action == "passwd") return passwd(*file, options);
  if (options.action == "remove") return remove(*file, options);
  if (options.action == "role") return set_role(*file, options);
  return list(*file);
}

CLI::Validator user_name_check() {
  return CLI::Validator(
      [](const std::string& name) {
        return valid_user_name(name) ? std::string()
                                     : "a user name is 1 to 64 of A-Z a-z 0-9 . _ @ -";
      },
      "NAME");
}

void add_allow_weak_option(CLI::App& action, UserOptions& options) {
  action.add_flag("--allow-weak", options.allow_weak,
                  "accept a password shorter than 10 characters, the account's name or a common "
                  "one (test rigs only)");
}

void add_users_file_option(CLI::App& action, UserOptions& options) {
  action.add_option("--users-file", options.users_file, "the users file ([http] users_file)")
      ->type_name("FILE")
      ->capture_default_str();
}

}  // namespace

Subcommand add_user(CLI::App& app) {
  auto options = std::make_shared<UserOptions>();
  CLI::App* user = app.add_subcommand("user", "the web console's accounts: add, passwd, role, remove, list");
  user->require_subcommand(1);
  user->footer(
      "Examples:\n"
      "  tiltgate user add alice --role admin        (the password typed twice, not shown)\n"
      "  echo \"$PASSWORD\" | tiltgate user add plc-viewer --role viewer\n"
      "  tiltgate user role alice --role viewer       (her sessions end at once)\n"
      "  tiltgate user list --users-file /etc/tiltgate/users\n"
      "Roles: viewer (sees everything, changes nothing), operator (also zero, filter and the "
      "other operator settings), admin (also address, baud, restart, scan, raw frames and the "
      "configuration). A password has at least 10 characters, is not the account's name and not a "
      "common one (--allow-weak: any, for test rigs). Passwords are kept as argon2id hashes only.\n"
      "Exit status: 0 done, 1 failed (the file, a name, the password), 2 usage.");
  const auto action = [&](const char* name, const char* help) {
    CLI::App* command = user->add_subcommand(name, help);
    command->callback([options, name] { options->action = name; });
    add_users_file_option(*command, *options);
    return command;
  };
  // Each action names its account; add and role give a role.
  const auto account_action = [&](const char* name, const char* help) {
    CLI::App* command = action(name, help);
    command->add_option("NAME", options->name, "the account's name")
        ->required()
        ->check(user_name_check());
    return command;
  };
  const auto role_option = [&](CLI::App& command) {
    command.add_option("--role", options->role, "viewer, operator or admin")
        ->required()
        ->check(CLI::IsMember({"viewer", "operator", "admin"}));
  };
  CLI::App* add_command = account_action("add", "add an account; the file is made if missing");
  role_option(*add_command);
  add_allow_weak_option(*add_command, *options);
  add_allow_weak_option(*account_action("passwd", "set an account's password"), *options);
  role_option(*account_action("role", "give an account another role"));
  account_action("remove", "remove an account");
  action("list", "the accounts' names and roles");
  return {user, [options] { return user_command(*options); }};
}

}  // namespace tiltgate
