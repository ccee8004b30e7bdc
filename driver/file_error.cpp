#include "driver/file_error.h"

#include <fmt/format.h>

namespace tiltgate {

std::string FileError::to_string() const {
  std::string out = file;
  if (line > 0) out += fmt::format(":{}:{}", line, column);
  out += ": ";
  if (!key.empty()) out += key + ": ";
  return out + message;
}

}  // namespace tiltgate
