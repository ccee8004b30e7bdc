// Giving up root: `tiltgate run` may be started as root to open its ttys and bind port 502,
// then serves as an unprivileged user ([server] user) for the rest of its life.
#pragma once

#include <string>

#include "driver/expected.h"

namespace tiltgate {

// Switches the whole process to `user`: its group, its supplementary groups (dialout, for ttys
// reopened after a cable pull) and its uid, for good (root cannot be regained). Already that
// user: nothing to do. Any other user than root cannot switch and gets an error saying so.
Expected<Done, std::string> run_as_user(const std::string& user);

}  // namespace tiltgate
