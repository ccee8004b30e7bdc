#include "config/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tiltgate::config {

Expected<std::string, std::string> read_text_file(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    return Unexpected(std::string("is a directory, expected a file"));
  std::ifstream file(path, std::ios::binary);
  if (!file) return Unexpected("cannot open: " + std::string(std::strerror(errno)));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) return Unexpected(std::string("cannot read the file"));
  return text.str();
}

}  // namespace tiltgate::config
