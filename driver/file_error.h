// A problem found in a file the gateway reads (a configuration, a map file, a device profile),
// at its place: what the user is shown, compiler style.
#pragma once

#include <string>
#include <vector>

namespace tiltgate {

struct FileError {
  std::string file;
  int line = 0;         // 1-based; 0 when the problem has no one place (an unreadable file)
  int column = 0;       // 1-based
  std::string key;      // "server.port", "bus[0].baud", "sensor[2].unit_id"; empty for syntax
  std::string message;  // what is wrong and what is expected

  // "FILE:LINE:COL: KEY: message", or "FILE: KEY: message" when there is no line.
  std::string to_string() const;
};

using FileErrors = std::vector<FileError>;

}  // namespace tiltgate
