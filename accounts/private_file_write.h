// Replacing a small file that only its owner and group may read (the users file), so that a
// crash at any moment leaves the old file or the new one, whole.
#pragma once

#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

// Writes `text` to a new temporary file beside `path` (mode 0640), syncs it, renames it over
// `path` and syncs the folder. The new file keeps the owner and group of the file it replaces;
// a new one gets its folder's group, where the process may give it (root, or a member). On any
// error the old file is untouched and the temporary one removed.
Expected<Done, std::string> write_private_file(const std::string& path, std::string_view text);

}  // namespace tiltgate
