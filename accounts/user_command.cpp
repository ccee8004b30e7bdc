// Each action loads the file, changes one account and saves it whole (atomically); the
// password is read after the checks that need none, so a mistake costs no typing.
#include "accounts/user_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "accounts/password_input.h"
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

// `add` starts a file when there is none; every other action needs it.
Expected<UsersFile, std::string> file_for(const UserOptions& options) {
  std::error_code ec;
  if (options.action == "add" && !std::filesystem::exists(options.users_file, ec) && !ec)
    return UsersFile{};
  return UsersFile::load(options.users_file);
}

int add(UsersFile& file, const UserOptions& options) {
  if (file.find(options.name) != nullptr)
    return failed(fmt::format("{}: an account named {} exists already (`tiltgate user passwd {}` "
                              "changes its password)",
                              options.users_file, options.name, options.name));
  auto password = read_new_password(options.name);
  if (!password) return failed(password.error());
  const Role role = *parse_role(options.role);  // checked by CLI11
  if (auto added = file.add(options.name, role, *password); !added) return failed(added.error());
  return saved(file, options.users_file,
               fmt::format("added {} ({})", options.name, role_name(role)));
}

int passwd(UsersFile& file, const UserOptions& options) {
  if (file.find(options.name) == nullptr)
    return failed(fmt::format("{}: no account named {}", options.users_file, options.name));
  auto password = read_new_password(options.name);
  if (!password) return failed(password.error());
  if (auto set = file.set_password(options.name, *password); !set) return failed(set.error());
  return saved(file, options.users_file, fmt::format("new password for {}", options.name));
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

void add_users_file_option(CLI::App& action, UserOptions& options) {
  action.add_option("--users-file", options.users_file, "the users file ([http] users_file)")
      ->type_name("FILE")
      ->capture_default_str();
}

}  // namespace

Subcommand add_user(CLI::App& app) {
  auto options = std::make_shared<UserOptions>();
  CLI::App* user = app.add_subcommand("user", "the web console's accounts: add, passwd, remove, list");
  user->require_subcommand(1);
  user->footer(
      "Examples:\n"
      "  tiltgate user add alice --role admin        (the password typed twice, not shown)\n"
      "  echo \"$PASSWORD\" | tiltgate user add plc-viewer --role viewer\n"
      "  tiltgate user list --users-file /etc/tiltgate/users\n"
      "Roles: viewer (sees everything, changes nothing), operator (also zero, filter and the "
      "other operator settings), admin (also address, baud, restart, scan, raw frames and the "
      "configuration). Passwords are kept as argon2id hashes only.\n"
      "Exit status: 0 done, 1 failed (the file, a name, the password), 2 usage.");
  const auto action = [&](const char* name, const char* help) {
    CLI::App* command = user->add_subcommand(name, help);
    command->callback([options, name] { options->action = name; });
    add_users_file_option(*command, *options);
    return command;
  };
  CLI::App* add_command = action("add", "add an account; the file is made if missing");
  add_command->add_option("NAME", options->name, "the account's name")
      ->required()
      ->check(user_name_check());
  add_command->add_option("--role", options->role, "viewer, operator or admin")
      ->required()
      ->check(CLI::IsMember({"viewer", "operator", "admin"}));
  action("passwd", "set an account's password")
      ->add_option("NAME", options->name, "the account's name")
      ->required()
      ->check(user_name_check());
  action("remove", "remove an account")
      ->add_option("NAME", options->name, "the account's name")
      ->required()
      ->check(user_name_check());
  action("list", "the accounts' names and roles");
  return {user, [options] { return user_command(*options); }};
}

}  // namespace tiltgate
