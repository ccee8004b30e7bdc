// Replacing a small file whole (the users file, the configuration), so that a crash at any
// moment leaves the old file or the new one, whole.
#pragma once

#include <sys/types.h>

#include <cstdint>

#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

// What mode the new file gets.
enum class FileMode : std::uint8_t {
  given,        // always the mode given (the users file: 0640, whatever the old file had)
  keep_old,     // the old file's, and the one given only for a new file (a configuration file)
};

// Writes `text` to a new temporary file beside `path`, syncs it, renames it over `path` and
// syncs the folder. The new file keeps the owner and group of the file it replaces, where the
// process may give them (root: so root editing the gateway's file leaves it the gateway's); a
// new one gets its folder's group where it may; otherwise it is the process's. On any error
// the old file is untouched and the temporary one removed.
Expected<Done, std::string> write_whole_file(const std::string& path, std::string_view text,
                                             mode_t mode, FileMode rule);

}  // namespace tiltgate
