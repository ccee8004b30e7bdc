// Reading the users file: each line an account, a comment or blank; every wrong line skipped and
// reported at its number, without its text (it may hold a password typed in by hand).
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <set>
#include <sstream>

#include "accounts/users_file.h"

namespace tiltgate {

namespace {

constexpr std::size_t kMaxNameLength = 64;

bool name_character(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '@' || c == '-';
}

std::string_view trimmed(std::string_view text) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && space(text.front())) text.remove_prefix(1);
  while (!text.empty() && space(text.back())) text.remove_suffix(1);
  return text;
}

// What libsodium writes (and verifies): "$argon2id$..." or the older "$argon2i$...", in the
// characters of its encoding (base64 without padding, digits, "$,=").
bool looks_like_argon2_hash(std::string_view hash) {
  if (!hash.starts_with("$argon2id$") && !hash.starts_with("$argon2i$")) return false;
  return std::all_of(hash.begin(), hash.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
           c == '$' || c == ',' || c == '=' || c == '+' || c == '/';
  });
}

// The account of one line, or what is wrong with it (with no text of the hash field).
Expected<UserAccount, std::string> parse_account(std::string_view line) {
  const std::size_t first = line.find(':');
  const std::size_t second = first == std::string_view::npos ? first : line.find(':', first + 1);
  if (second == std::string_view::npos)
    return Unexpected(std::string("expected NAME:ROLE:HASH (an account made by `tiltgate user add`)"));
  const std::string_view name = line.substr(0, first);
  const std::string_view role_text = line.substr(first + 1, second - first - 1);
  const std::string_view hash = line.substr(second + 1);
  if (!valid_user_name(name))
    return Unexpected(fmt::format("user name \"{}\" is not 1 to {} of A-Z a-z 0-9 . _ @ -",
                                  name.substr(0, kMaxNameLength), kMaxNameLength));
  const std::optional<Role> role = parse_role(role_text);
  if (!role)
    return Unexpected(fmt::format("{}: role \"{}\" is not viewer, operator or admin", name,
                                  role_text.substr(0, 16)));
  if (!looks_like_argon2_hash(hash))
    return Unexpected(fmt::format("{}: the third field is not an argon2id hash (set the password "
                                  "with `tiltgate user passwd {}`)",
                                  name, name));
  return UserAccount{std::string(name), *role, std::string(hash)};
}

}  // namespace

bool valid_user_name(std::string_view name) {
  return !name.empty() && name.size() <= kMaxNameLength &&
         std::all_of(name.begin(), name.end(), name_character);
}

UsersFile UsersFile::parse(std::string_view text, const std::string& path) {
  UsersFile file;
  // The names a skipped line gives: none of them is an account, whatever the other lines say.
  std::set<std::string, std::less<>> refused;
  std::size_t number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    const std::string_view raw = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    const std::string_view line = trimmed(raw);
    if (line.empty() || line.front() == '#') {
      file.lines_.push_back({false, std::string(line)});
      continue;
    }
    auto account = parse_account(line);
    std::string problem;
    if (!account)
      problem = account.error();
    else if (file.find(account->name) != nullptr || refused.contains(account->name))
      problem = fmt::format("{}: a second account of that name", account->name);
    if (problem.empty()) {
      file.lines_.push_back({true, account->name});
      file.accounts_.push_back(std::move(*account));
      continue;
    }
    const std::string_view name = line.substr(0, line.find(':'));
    const bool named = line.find(':') != std::string_view::npos && valid_user_name(name);
    if (named) refused.emplace(name);
    file.skipped_.push_back(fmt::format("{}:{}: {}{}", path, number, problem,
                                        named ? fmt::format(" (no login for {} until the line is "
                                                            "fixed or removed)",
                                                            name)
                                              : std::string()));
  }
  std::erase_if(file.accounts_, [&](const UserAccount& a) { return refused.contains(a.name); });
  std::erase_if(file.lines_,
                [&](const Line& l) { return l.is_account && refused.contains(l.text); });
  return file;
}

Expected<UsersFile, std::string> UsersFile::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;
    return Unexpected(fmt::format(
        "{}: cannot read the users file: {}{}", path, std::strerror(error),
        error == ENOENT ? " (make it with `tiltgate user add NAME --role admin --users-file " +
                              path + "`)"
                        : std::string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Unexpected(fmt::format("{}: cannot read the users file", path));
  return parse(text.str(), path);
}

}  // namespace tiltgate
