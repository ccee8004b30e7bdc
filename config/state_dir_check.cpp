#include "config/state_dir_check.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace tiltgate::config {

std::optional<std::string> state_dir_problem(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path existing = dir;
  while (!fs::exists(existing, error)) {
    if (error || !existing.has_parent_path() || existing.parent_path() == existing)
      return fmt::format("{}: {}", existing.string(),
                         error ? error.message() : std::string("no folder above it exists"));
    existing = existing.parent_path();
  }
  if (!fs::is_directory(existing, error))
    return fmt::format("{} is not a directory", existing.string());
  // W_OK and X_OK: create and rename files in it, as the store does.
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    return fmt::format("{} is not writable by uid {}: {}", existing.string(), ::geteuid(),
                       std::strerror(errno));
  return std::nullopt;
}

}  // namespace tiltgate::config
