// Reading a whole text file (a configuration or a map file), with the reason when it cannot be.
#pragma once

#include <string>

#include "driver/expected.h"

namespace tiltgate::config {

// The file's contents, or why not: "is a directory, expected a file", "cannot open: ...".
Expected<std::string, std::string> read_text_file(const std::string& path);

}  // namespace tiltgate::config
