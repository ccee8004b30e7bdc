#include "app/run_as_user.h"

#include <fmt/format.h>
#include <grp.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace tiltgate {

namespace {

std::string last_error() { return std::strerror(errno); }

}  // namespace

Expected<ServingUser, std::string> find_user(const std::string& name) {
  std::vector<char> buffer(16384);
  passwd entry{};
  passwd* found = nullptr;
  const int lookup = getpwnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found);
  if (found == nullptr)
    return Unexpected{lookup != 0
                          ? fmt::format("cannot look up user '{}': {}", name, std::strerror(lookup))
                          : fmt::format("there is no user '{}' on this machine", name)};
  return ServingUser{found->pw_name, found->pw_uid, found->pw_gid};
}

std::vector<std::string> make_folders_for(const ServingUser& user,
                                          const std::vector<std::filesystem::path>& folders) {
  namespace fs = std::filesystem;
  std::vector<std::string> errors;
  for (const fs::path& folder : folders) {
    std::error_code ec;
    if (folder.empty() || fs::exists(fs::symlink_status(folder, ec))) continue;
    if (folder.has_parent_path()) fs::create_directories(folder.parent_path(), ec);
    // mkdir, not create_directories: one that appeared meanwhile is not someone else's to chown.
    if (!ec && ::mkdir(folder.c_str(), 0750) != 0) ec = {errno, std::generic_category()};
    if (!ec && ::chown(folder.c_str(), user.uid, user.gid) != 0)
      ec = {errno, std::generic_category()};
    // Under a umask such as 0077 mkdir leaves the group out.
    if (!ec && ::chmod(folder.c_str(), 0750) != 0) ec = {errno, std::generic_category()};
    if (ec)
      errors.push_back(fmt::format("cannot make {} for user '{}': {}", folder.string(), user.name,
                                   ec.message()));
  }
  return errors;
}

Expected<Done, std::string> run_as_user(const ServingUser& user) {
  const uid_t uid = user.uid;
  const gid_t gid = user.gid;
  if (getuid() == uid && geteuid() == uid && getgid() == gid && getegid() == gid) return Done{};
  if (geteuid() != 0)
    return Unexpected{fmt::format("cannot switch to user '{}': started as uid {}, and only root "
                                  "can (start as '{}' or as root)",
                                  user.name, geteuid(), user.name)};
  // Groups first: once the uid is gone, so is the right to change them.
  if (initgroups(user.name.c_str(), gid) != 0)
    return Unexpected{fmt::format("cannot take the groups of user '{}': {}", user.name,
                                  last_error())};
  if (setgid(gid) != 0)
    return Unexpected{fmt::format("cannot switch to group {}: {}", gid, last_error())};
  if (setuid(uid) != 0)
    return Unexpected{fmt::format("cannot switch to user '{}': {}", user.name, last_error())};
  // setuid() from root sets all three uids; check that root really is out of reach.
  if (uid != 0 && setuid(0) == 0)
    return Unexpected{fmt::format("switched to user '{}' but could become root again", user.name)};
  return Done{};
}

}  // namespace tiltgate
