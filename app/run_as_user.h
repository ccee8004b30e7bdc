// Giving up root: `tiltgate run` may be started as root to open its ttys and bind port 502,
// then serves as an unprivileged user ([server] user) for the rest of its life.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

// [server] user as this machine knows it.
struct ServingUser {
  std::string name;
  uid_t uid = 0;
  gid_t gid = 0;  // its own group
};

Expected<ServingUser, std::string> find_user(const std::string& name);

// Still as root, before the switch: makes each folder in `folders` that does not exist yet
// (its missing parents as root's) and gives it to `user`, mode 0750, so what the gateway
// writes there once it serves as that user (the control socket, the stores) is that user's and
// can be replaced by it at a reload. A folder that exists is left as it is. The errors, one per
// folder that could not be made; the services say again what they then cannot do.
std::vector<std::string> make_folders_for(const ServingUser& user,
                                          const std::vector<std::filesystem::path>& folders);

// Switches the whole process to `user`: its group, its supplementary groups (dialout, for ttys
// reopened after a cable pull) and its uid, for good (root cannot be regained). Already that
// user: nothing to do. Any other user than root cannot switch and gets an error saying so.
Expected<Done, std::string> run_as_user(const ServingUser& user);

}  // namespace tiltgate
