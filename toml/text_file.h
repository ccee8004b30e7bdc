// Reading a whole text file (a configuration or a map file), with the reason when it cannot be.
#pragma once

#include <cstddef>
#include <string>

#include "driver/expected.h"

namespace tiltgate::toml_input {

// No configuration, map or profile comes near this; /dev/zero or a log file given by mistake
// would otherwise be read until memory runs out.
inline constexpr std::size_t kMaxTextFileBytes = 1024 * 1024;

// The contents of a regular file of at most kMaxTextFileBytes, or why not: "is a directory,
// expected a regular file", "is a FIFO, ...", "is 2097152 bytes, more than ...", "cannot
// open: ...". Never blocks: a FIFO is refused, not waited on.
Expected<std::string, std::string> read_text_file(const std::string& path);

// A file a configuration names to be read as TOML (a map file, a device profile): read_text_file,
// and its name must end in ".toml". Any other file is refused before it is parsed, so an error
// never shows where a file that is not TOML (/etc/shadow, a key) has its lines and words
// (docs/configuration.md, "Files a configuration names").
Expected<std::string, std::string> read_toml_file(const std::string& path);

}  // namespace tiltgate::toml_input
