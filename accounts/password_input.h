// Where `tiltgate user add` and `passwd` take a new password from: typed twice at the terminal
// without echo, or one line of standard input when that is not a terminal (a script's pipe).
#pragma once

#include <string>

#include "driver/expected.h"

namespace tiltgate {

// The password for `name`, or why there is none (end of input, the two typed differ).
Expected<std::string, std::string> read_new_password(const std::string& name);

}  // namespace tiltgate
