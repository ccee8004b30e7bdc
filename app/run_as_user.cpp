#include "app/run_as_user.h"

#include <fmt/format.h>
#include <grp.h>
#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace tiltgate {

namespace {

std::string last_error() { return std::strerror(errno); }

}  // namespace

Expected<Done, std::string> run_as_user(const std::string& user) {
  std::vector<char> buffer(16384);
  passwd entry{};
  passwd* found = nullptr;
  const int lookup = getpwnam_r(user.c_str(), &entry, buffer.data(), buffer.size(), &found);
  if (found == nullptr)
    return Unexpected{lookup != 0
                          ? fmt::format("cannot look up user '{}': {}", user, std::strerror(lookup))
                          : fmt::format("there is no user '{}' on this machine", user)};
  const uid_t uid = found->pw_uid;
  const gid_t gid = found->pw_gid;
  if (getuid() == uid && geteuid() == uid && getgid() == gid && getegid() == gid) return Done{};
  if (geteuid() != 0)
    return Unexpected{fmt::format("cannot switch to user '{}': started as uid {}, and only root "
                                  "can (start as '{}' or as root)",
                                  user, geteuid(), user)};
  // Groups first: once the uid is gone, so is the right to change them.
  if (initgroups(found->pw_name, gid) != 0)
    return Unexpected{fmt::format("cannot take the groups of user '{}': {}", user, last_error())};
  if (setgid(gid) != 0)
    return Unexpected{fmt::format("cannot switch to group {}: {}", gid, last_error())};
  if (setuid(uid) != 0)
    return Unexpected{fmt::format("cannot switch to user '{}': {}", user, last_error())};
  // setuid() from root sets all three uids; check that root really is out of reach.
  if (uid != 0 && setuid(0) == 0)
    return Unexpected{fmt::format("switched to user '{}' but could become root again", user)};
  return Done{};
}

}  // namespace tiltgate
